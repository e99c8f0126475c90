G90 G17
N1 (no G20 or G21 anywhere: the numbers pass through in the machine's units, with a warning)
N3 G0 X10. Y5. Z2.
N4 G1 Z-1. F100.
N5 G1 X20.
N6 M30
