G21 G90 G17
(Path control on grbl: it has none, so each is left out with one warning)
G1 X10. F300.
G1 Y10.
G1 X0.
M2
