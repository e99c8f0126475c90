N1 (stages of a small Fanuc program with corner words: an inch program)
N2 G17
N3 G0 X0. Y0. Z0.5
N4 F10.
N4 G1 Z-0.1
N5 G1 X2. ,R0.25
N6 G1 Y1. ,C0.1
N7 G1 X0.
N8 G0 Z0.5
N9 M30
