Depth = 5
Zsafe = 3
Feed = 120
G21
G90
G17
T1
M6
S9000
M3
G0 Z<Zsafe>
G0 X15 Y15
G1 Z<(-Depth)> F<Feed>
G0 Z<Zsafe>
G0 X<(15 + 50)> Y15
G1 Z<(-Depth)> F<Feed>
G0 Z<Zsafe>
if (Depth > 4) {
    G0 X40 Y15
    G1 Z-1 F<Feed>
    G0 Z<Zsafe>
}
M5
M30
