(Hexagon outline plus every built-in function (angles in degrees))
Rad = 25
Sides = 6
Step = (360 / Sides)
Apothem = (Rad * cos((Step / 2)))
(distance to a flat)
Edge = ((2 * Rad) * sin((Step / 2)))
Slope = tan(45)
(1)
Back = (asin(0.5) + acos(0.5))
(90)
Ang = (atan(1) + atan2(1, (-1)))
(45 + 135)
Diag = hypot(30, 40)
(50)
Root = sqrt((Diag * 2))
(10)
Chk = (((floor(2.7) + ceil(2.1)) + round(2.4)) + abs((-4)))
Pick = (min(Edge, Apothem) + max(1, 2))
Grow = ((exp(1) * ln(exp(2))) + log10(1000))
Circ = ((2 * 3.141592653589793) * Rad)
Kk = 0
G21
G90
G17
T1
M6
S9000
M3
G0 Z5
G0 X<(Rad + 5)> Y0
G1 Z-2 F150
while (Kk <= Sides) {
    G1 X<(Rad * cos((Kk * Step)))> Y<(Rad * sin((Kk * Step)))> F600
    Kk = (Kk + 1)
}
G0 Z5
M5
M30
