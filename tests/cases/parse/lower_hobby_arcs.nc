(circle and rounded slot, lowercase with line numbers)
(written by hand for a hobby router)
G21
G90
G17
N20 T1
M6
N30 S12000
M3
G0 Z5
G0 X30 Y20
G1 Z-1 F120
G2 X30 Y20 I-10 J0 F400
(full circle r10 around x20 y20)
G0 Z5
G0 X50 Y10
G1 Z-1 F120
G1 X70 F400
G3 X70 Y30 R10
G1 X50
G3 X50 Y10 R10
G0 Z5
M5
G0 X0 Y0
M30
