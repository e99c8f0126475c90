G21 G90 G17
N2 G0 X1. Y1. Z1.
N4 G0 X2.
N4 (a comment // in a comment)
N5 (a // in parentheses)
N6 M30
