G21 G90 G17
N1 (Spaces inside words  SPEC 2.2 , read as plain G-code and rs274 read them;)
N2 (a directive's and a wizard call's arguments stay apart.)
N7 G0 Z5.
N8 G0 X-10.5 Y10.5
N9 G1 Z-2. F100.
N10 G1 X10.5 Y-1.5
N11 G1 X20. Y20.
N12 G1 X30.
N13 G0 Z5.
N13 G0 X40.
N13 G1 Z-1.
N13 G0 Z5.
N13 G0 X25. Y28.66
N13 G1 Z-1.
N13 G0 Z5.
N13 G0 Y11.34
N13 G1 Z-1.
N13 G0 Z5.
N13 G0 X30. Y20.
N14 M30
