G21 G90 G17
N1 (G10 L1 and L10 with a lathe tool's Q, I, J: passed on as written)
N3 G10 L1 P1 R3. Z25. Q3. I10. J80.
N4 G10 L1 P2 Q2.
N5 G0 X0. Y0. Z10.
N6 G10 L1 P3 Z6. Q9. J-5.5
N7 T1 M6
N9 G1 Z30. F300.
N10 G0 Z10.
N11 M30
