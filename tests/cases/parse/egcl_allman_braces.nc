(Row of slots cut alternately up and down: braces on their own lines)
NumSlots = 5
Pitch = 12
SlotLen = 40
Depth = 3
Zsafe = 5
Count = 0
G21
G90
G17
T1
M6
S9000
M3
G0 Z<Zsafe>
while (Count < NumSlots) {
    if ((Count % 2) == 0) {
        G0 X<(Count * Pitch)> Y0
        G1 Z<(-Depth)> F120
        G1 Y<SlotLen> F500
    } else {
        G0 X<(Count * Pitch)> Y<SlotLen>
        G1 Z<(-Depth)> F120
        G1 Y0 F500
    }
    G0 Z<Zsafe>
    Count = (Count + 1)
}
M5
M30
