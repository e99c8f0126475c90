G21 G90 G17
(a retract after a tool change must be written even if Z did not change)
T1
M0 (change to tool 1)
G0 Z25.
G0 X10. Y10.
G1 Z-1. F100.
G1 X20.
G0 Z25.
M5
T2
M0 (change to tool 2)
G0 Z25.
G0 X20. Y0.
M0
G0 Z25.
M2
