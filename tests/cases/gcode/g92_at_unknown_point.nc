G21 G90 G17
N1 (G92 where only the machine knows the point: passed through, the moves after it in its frame)
N3 G0 X0. Y0.
N4 G92 Z0.
N5 G0 Z5.
N6 G1 Z-1. F100.
N7 G2 X10. Y0. I5. J0.
N8 G0 Z5.
N9 G92.1
N10 G0 Z10.
N11 M30
