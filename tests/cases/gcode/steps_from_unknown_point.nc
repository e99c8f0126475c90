G21 G90 G17
(Steps on axes only the machine knows: written as steps, between G91 and G90)
G91 G1 X10. F100.
G90
G91 G1 Y5. Z-1.
G90
G0 X0. Y0.
G91 G1 X5. Z-1.
G90
G1 Y-3.
G0 Z10.
M2
