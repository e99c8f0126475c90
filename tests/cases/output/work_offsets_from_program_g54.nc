G21 G90 G17
N1 (G54 set by the program before it selects a system goes to the machine: G55's G10 L2 values are then measured from where the program put G54, and folding G55 assumes nothing of the machine: no warning)
N3 G10 L2 P1 X-300. Y-200. Z-50.
N4 G10 L2 P2 X-200. Y-150. Z-50.
N5 G54
N6 G0 X110. Y60. Z10.
N7 G1 Z-1. F200.
N8 M30
