G21 G90 G17
N1 (with --units inch the F before G21 is in inches: converted, and G21 fixes the output units)
N3 G0 X0. Y0. Z5.
N4 G1 X1. F2540.
N5 M30
