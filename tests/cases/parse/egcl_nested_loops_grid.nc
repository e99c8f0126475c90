(4 x 3 grid of pecked holes in serpentine order: nested while loops)
Cols = 4
Rows = 3
Pitch = 15
Depth = 9
Peck = 3
Zsafe = 5
Row = 0
G21
G90
G17
T2
M6
S2000
M3
M8
G0 Z<Zsafe>
while (Row < Rows) {
    Col = 0
    while (Col < Cols) {
        (even rows left to right, odd rows right to left)
        if ((Row % 2) == 0) {
            Xh = (Col * Pitch)
        } else {
            Xh = (((Cols - 1) - Col) * Pitch)
        }
        G0 X<Xh> Y<(Row * Pitch)>
        Zd = 0
        while (Zd < Depth) {
            G0 Z<(0.5 - Zd)>
            (rapid back to just above the last peck)
            Zd = min((Zd + Peck), Depth)
            G1 Z<(-Zd)> F80
            G0 Z1
        }
        G0 Z<Zsafe>
        Col = (Col + 1)
    }
    Row = (Row + 1)
}
M9
M5
M30
