G90 G17
N1 (a program, then notes after its end: compiled, with one note)
N2 F100.
N2 G21
N3 G0 X0. Y0. Z5.
N4 G1 X10.
N5 M30
