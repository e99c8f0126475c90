(Short loops and branches written on one line each)
Pitch = 10
Depth = 2
Deep = false
Zsafe = 5
ii = 0
G21
G90
G17
T1
M6
S8000
M3
G0 Z<Zsafe>
G0 X0 Y0
G1 Z<(-Depth)> F100
while (ii < 3) {
    G1 X<ii> F400
    ii = (ii + 1)
}
while (ii < 6) {
    G1 X<(ii * Pitch)>
    ii = (ii + 1)
}
if Deep {
    G1 Z<((-2) * Depth)> F100
} else {
    G1 Z<((-Depth) - 0.5)> F100
}
while (ii > 0) {
    ii = (ii - 1)
    G1 X<(ii * Pitch)> Y5
}
if (ii == 0) {
    G0 Z<Zsafe>
}
M5
M30
