G21 G90 G17
N1 (a plain program: DEBUG shows a user parameter never set as 0, as rs274 does, and #5420, which only the machine knows, as ###### where rs274 prints its position)
N3 (DEBUG, five is #5, the machine's x is #5420)
N4 G0 X1. Y1. Z1.
N5 M30
