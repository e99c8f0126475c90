(grbl engraving job - 20 x 20 square, diagonal and a tick mark)
(units mm, origin at the lower left corner of the stock top)
G21
G90
G17
G0 Z5
G0 X0 Y0
M3 S10000
G1 Z-0.5 F100
G1 X20 Y0 F300
G1 X20 Y20
G1 X0 Y20
G1 X0 Y0
G1 X20 Y20
G0 Z5
G0 X1 Y1
G1 Z-0.5 F100
G1 X1 Y2 F100
G0 Z5
M5
G0 X0 Y0
M2
