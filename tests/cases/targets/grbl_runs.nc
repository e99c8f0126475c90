G21 G90 G17
(grbl 1.1 runs these as they are; the tool change is a stop)
T1
M0 (change to tool 1)
G0 X10. Y10. Z5.
G1 Z-1. F100.
G2 X20. Y10. I5. J0.
G4 P2.
M56
G55
G91 G28 Z0.
G90
M2
