G21 G90 G17
N1 (a plain program: DEBUG in a subroutine shows the call's argument #1, which the program names nowhere else; rs274 prints 3.000000, and so does ger)
N6 G0 X1. Y1. Z1.
N4 (DEBUG, the argument is #1)
N8 M30
