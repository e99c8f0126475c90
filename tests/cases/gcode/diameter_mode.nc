G21 G90 G17
N1 (G7: X words are diameters, halved as they are read, also on the line that sets it and under G91; G8 ends it)
N2 G18
N3 G0 X0. Z5.
N4 G0 X10.
N5 G1 X5. Z-5. F100.
N6 G1 X10. Z-20.
N8 G2 X15. Z-25. K-5. I0.
N9 G0 X20.
N10 M30
