(Inch job whose stock is the cut bounds plus a 0.25 in margin)
SetUnits("inch")
SetMargin(0.25)
SetTool(1, 0.25, 2, "flat")
SetTool(3, 0.125, 1.75, "vee")
SetOffset(57, 4, 2, 0)
G20
G90
G17
T3
M6
S18000
M3
G57
G0 Z0.25
G0 X0.5 Y0.5
G1 Z-0.02 F10
G1 X2.5 F30
G1 Y1
G1 X0.5
G1 Y0.5
G0 Z0.25
M5
M30
