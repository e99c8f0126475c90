O500 (main)
(CAM-style compact blocks driven by variables: symbolic words without spaces)
Rows = 3
Yst = 10
Pitch = 8.5
Row = 0
G21
G90
G17
N20 T1
M6
N30 S10000
M3
G0 Z5
while (Row < Rows) {
    G0 X0 Y<(Yst + (Row * Pitch))>
    G1 Z-1 F150
    G1 X60 F900
    G0 Z5
    Row = (Row + 1)
}
M5
M30
