(Face the stock, then a slot, a helical bore and a curve: both call forms)
SetUnits("mm")
SetPart(100, 60, 20)
SetZero(0, 0, 0.5)
SetTool(1, 12, 60, "flat")
SetTool(2, 6, 55, "flat")
Zsafe = 5
BoreDia = 22
G21
G90
G17
T1
M6
S6000
M3
M8
G0 Z<Zsafe>
Facing(100, 60, 0.5)
G0 Z<Zsafe>
T2
M6
S10000
M3
Slot(15, 15, 85, 15, 6, 3)
Helix(50, 40, (BoreDia / 2), 10, 1)
Bezier(10, 50, 30, 58, 70, 42, 90, 50, 1)
CirclePocket(25, 40, ((BoreDia / 2) - 3), 4)
G0 Z25
M9
M5
M30
