G21 G90 G17
(output options)
T2
M0 (change to tool 2)
S12000. M3
G0 X0. Y0. Z5.
G1 Z-1. F200.
G2 X20. Y0. I10. J0.
G3 X0. Y0. I-10. J0.
G2 X0. Y0. I10. J0.
G4 P0.5
M5
M2
