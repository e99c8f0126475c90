(Every example of SPEC §2–§3, as written there (P0X, the deliberate)
(non-name, is in tests/cases/syntax/name_letter_digit.egc).)
SetUnits("mm")
SetZero(0.25, 0.25, 0.1)
SetTool(1, 6.35)
G1 X1
Y2
G1
G1 X-0.5 X2 Y10
M6 T1
G54.1
G1 X1 Y2
G0 X<(CenX + Rr)> Y<CenY> Z<Zsafe>
G1 X1
G21
G1 Y250
T1
M6
M6 T1
DE = 1
CenX = 2
Tool_num_1 = true
dx1 = 3
if (Tool_num_1 == true) {
    M6 T1
} else if Big {
    M6 T3
} else {
    M6 T2
}
while (DPass <= abs(Depth)) {
    G1 Z<(-DPass)>
    DPass = (DPass + Step)
}
M98 P1000 L3
M98 P31000
Pocket(75, 30, 10)
holesLine(NumHoles, dx1, dy1, Xini1, Yini1, DepthBC, Zseg)
M30
O1000
    G1 X1
    M99
