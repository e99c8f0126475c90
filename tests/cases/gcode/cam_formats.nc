G21 G90 G17
N3 (HSS Twist Drill, 3mm  R )
N4 (a comment line; G0 X99 must not run)
$H
N7 G91 G28 Z0.
N7 G90
N9 G0 Z5.
N9 (spaces inside a word)
N10 G0 X10. Y20.5
N11 M62 P1.
N12 G1 Z-1. F100.
N12 (G0 Z50)
N13 M8 G1 Y40.
/N14 G0 Z2.
N14 M30
