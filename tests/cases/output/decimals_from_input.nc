G21 G90 G17
N1 (the output keeps the input's precision: 5 decimals here, at most 6)
N3 G0 X0. Y0. Z1.
N4 G1 X1.23456 F100.
N5 G2 X2.46912 Y0. I0.61728 J0.
N6 G1 Y0.123457
N7 M30
