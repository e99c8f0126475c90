G21 G90 G17
(a grbl program: --target grbl reads its dwell as grbl does, 7 s)
S12000. M3
G4 P7.
G0 X0. Y0. Z5.
M2
