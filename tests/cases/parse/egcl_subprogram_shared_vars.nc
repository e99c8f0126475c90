(Variables are global: the subprogram reads and advances them)
Pitch = 20
Depth = 2
SlotNo = 0
Zsafe = 5
G21
G90
G17
T1
M6
S9000
M3
G0 Z<Zsafe>
M98 P2000 L4
(four slots)
G0 Z25
M5
M30
O2000
    (one slot at X = SlotNo * Pitch)
    G0 X<(SlotNo * Pitch)> Y0
    G1 Z<(-Depth)> F120
    G1 Y30 F500
    G0 Z<Zsafe>
    SlotNo = (SlotNo + 1)
    M99
