(Parenthesis comments wherever EGCL reads them as comments)
(Job: cover plate,
 two through holes and a spot in the middle)
Depth = 5
(mm, through the plate)
Zsafe = 3
Feed = 120
(mm/min)
G21
G90
G17
(metric, absolute, XY plane)
T1
M6
(6 mm end mill)
S9000
M3
G0 Z<Zsafe>
(safe height)
G0 X15 Y15
G1 Z<(-Depth)> F<Feed>
(first hole)
G0 Z<Zsafe>
G0 X<(15 + 50)> Y15
(second hole, 50 mm to the right)
G1 Z<(-Depth)> F<Feed>
G0 Z<Zsafe>
if (Depth > 4) {
    (thick plate: also spot the middle)
    (spot 1 mm deep)
    G0 X40 Y15
    G1 Z-1 F<Feed>
    G0 Z<Zsafe>
}
M5
(spindle off)
M30
