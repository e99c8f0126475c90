G21 G90 G17
(--numbers keep: the program's own N words, each once)
N20 T1 M6
N30 S1000. M3
G0 X0. Y0.
(a line without N gets none)
N160 G0 Z5.
N170 G0 X10. Y5.
G0 Z1.
G1 Z-2. F50.
G0 Z5.
(several lines: N on the first)
N190 G1 X11. F100.
(the first turn only)
G1 X12.
(the first turn only)
G1 Y8.
(a subprogram's lines: none)
N230 G0 X0. Y0.
N240 M30
