G90 G17
N2 (a tape: the program ends at its next % line, M30 or not; what follows is not read, with a note)
N3 F100.
N3 G21
N4 G0 X0. Y0. Z5.
N5 G1 Z-1.
N7 G1 X10.
N7 M30
