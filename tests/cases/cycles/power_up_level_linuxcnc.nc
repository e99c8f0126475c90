G21 G90 G17
N1 (No G98 or G99 before the cycles, read as LinuxCNC: the R plane  G99 ,)
N2 (as rs274 starts, with a warning.)
N4 G0 X0. Y0. Z10.
N5 G0 X5. Y5.
N5 G0 Z2.
N5 G1 Z-2. F100.
N5 G0 Z2.
N6 G0 X10.
N6 G1 Z-2.
N6 G0 Z2.
N8 M30
