G21 G90 G17
N1 (work offsets the program does not give whole pass through with a warning each, which says how to fold them: SetOffset for G55-G59, G10 L2 for all; G55 given only its X goes to the machine with that X)
N3 G0 X0. Y0. Z10.
N4 G10 L2 P2 X200.
N5 G55
N6 G0 X10. Y10.
N7 G59.1
N8 G0 X10. Y10.
N9 M30
