G21 G90 G17
N1 (Fanuc's G86 bores, stops the spindle and rapids out: it has no dwell word)
N3 S800. M3
N4 G0 X0. Y0. Z10.
N6 G0 X10. Y10.
N6 G0 Z2.
N6 G1 Z-5. F100.
N6 M5 G0 Z10.
N6 M3
N7 G0 X20.
N7 G0 Z2.
N7 G1 Z-5.
N7 M5 G0 Z10.
N7 M3
N9 M30
