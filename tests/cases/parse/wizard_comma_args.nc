(Hole lines and bolt circles with EGCL comma-form wizard calls)
SetUnits("mm")
SetPart(150, 100, 15)
NumHoles = 5
dx1 = 20
dy1 = 0
Xini1 = 25
Yini1 = 20
DepthBC = 8
Zseg = 5
G21
G90
G17
T3
M6
S2200
M3
M8
G0 Z<Zseg>
holesLine(NumHoles, dx1, dy1, Xini1, Yini1, DepthBC, Zseg)
holesLine(NumHoles, dx1, dy1, Xini1, (Yini1 + 60), DepthBC, Zseg)
circArray(75, 50, 20, 6, 0, DepthBC, Zseg)
BoltCircle(75, 50, 35, 8, 22.5, (DepthBC / 2), Zseg)
G0 Z25
M9
M5
M30
