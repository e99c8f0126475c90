(Machine setup directives, then the same square cut in two work offsets (mm))
SetUnits("mm")
SetPart(100, 80, 20)
SetZero(0.25, 0.25, 0.1)
SetTool(1, 6.35, 50, "flat")
SetTool(2, 3, 45, "ball")
SetTool(5, 6, 70, "drill")
SetOffset(55, 100, 50, 0)
SetOffset(56, 0, 150, -5)
G21
G90
G17
T1
M6
S12000
M3
G54
G0 Z5
G0 X10 Y10
G1 Z-1 F200
G1 X40 F800
G1 Y30
G1 X10
G1 Y10
G0 Z5
G55
G0 X10 Y10
G1 Z-1 F200
G1 X40 F800
G1 Y30
G1 X10
G1 Y10
G0 Z5
M5
M30
