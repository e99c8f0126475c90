(Rectangular pockets with the Pocket wizard: space-separated arguments)
SetUnits("mm")
SetPart(120, 80, 20)
SetTool(1, 6, 50, "flat")
Wid = 40
Hgt = 25
Depth = 4
G21
G90
G17
T1
M6
S10000
M3
G0 Z5
G0 X20 Y20
Pocket(75, 30, 10)
G0 Z5
G0 X80 Y40
Pocket(Wid, Hgt, (Depth * 2), "mm")
G0 Z5
G0 X<(60 - (Wid / 2))> Y10
pocket(20, 10, Depth)
G0 Z25
M5
M30
