(Square outline cut in depth passes: while with braces on the same line)
Depth = (-5)
Step = 1.5
Side = 60
Zsafe = 5
DPass = Step
G21
G90
G17
T1
M6
S10000
M3
G0 Z<Zsafe>
G0 X0 Y0
while (DPass <= abs(Depth)) {
    G1 Z<(-DPass)> F100
    G1 X<Side> F600
    G1 Y<Side>
    G1 X0
    G1 Y0
    DPass = (DPass + Step)
}
(last pass at the full depth when the steps did not land on it)
if ((DPass - Step) < abs(Depth)) {
    G1 Z<Depth> F100
    G1 X<Side> F600
    G1 Y<Side>
    G1 X0
    G1 Y0
}
G0 Z<Zsafe>
M5
M30
