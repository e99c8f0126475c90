G21 G90 G17
(grbl counts G4 in 50 ms steps in 16 bits: 4000 s wraps round to 723.2 s; a warning at the first, the output as written)
S500. M3
G4 P3276.75
G0 X10. Y10. Z5.
G4 P4000.
G4 P5000.
M2
