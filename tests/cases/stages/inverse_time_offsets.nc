N1 (G93 at the offsets stage, before the absolute pass turns each F into a feed per minute: an inverse-time F keeps all its digits, F0.0001 a move of 10,000 minutes, not F0)
N2 G17
N2 G90
N3 G0 X0. Y0. Z5.
N4 G93
N5 F0.0001
N5 G1 X10.
N6 F0.3333
N6 G1 X20.
N7 G94
N8 F300.
N8 G1 X0.
N9 M30
