G21 G90 G17
N1 (No G98 or G99 before the cycles: the generic flavour returns to the)
N2 (initial level  G98 , as Fanuc, Haas and Mach3 start, with a warning.)
N4 G0 X0. Y0. Z10.
N5 G0 X5. Y5.
N5 G0 Z2.
N5 G1 Z-2. F100.
N5 G0 Z10.
N6 G0 X10.
N6 G0 Z2.
N6 G1 Z-2.
N6 G0 Z10.
N8 M30
