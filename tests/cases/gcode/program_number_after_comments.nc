G21 G90 G17
N1 (header comment)
N2 (Part: plate)
N5 G0 X1. Y1. Z5.
N6 M30
