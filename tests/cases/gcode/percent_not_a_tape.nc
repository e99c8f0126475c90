G90 G17
N1 (a % line in a program that does not start with one closes nothing: it is skipped)
N2 F100.
N2 G21
N3 G0 X0. Y0. Z5.
N5 G1 X10.
N6 M30
