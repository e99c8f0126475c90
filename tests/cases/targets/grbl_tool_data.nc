G21 G90 G17
(G10 L1: tool 1 radius 3, length 25; G43 H1 folds the length)
T1
M0 (change to tool 1)
G0 X-20. Y-20. Z30.
G1 Z24. F300.
G1 X-2.121 Y2.121
G2 X0. Y3. I2.121 J-2.121
G1 X37.
G1 Y30.
G1 X60. Y40.
G0 Z10.
M2
