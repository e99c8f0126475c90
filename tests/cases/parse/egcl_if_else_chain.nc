(Tool, speed and feed chosen from the material: if / else if / else)
Material = 2
(1 aluminium, 2 brass, 3 acrylic)
Tool_num_1 = false
Big = (Material == 3)
Depth = 1.5
G21
G90
G17
if (Tool_num_1 == true) {
    M6 T1
} else if Big {
    M6 T3
} else {
    M6 T2
}
if (Material == 1) {
    Speed = 12000
    Feed = 900
} else if (Material == 2) {
    Speed = 8000
    Feed = 500
} else {
    Speed = 18000
    Feed = 1500
}
S<Speed>
M3
if (Material != 3) {
    M8
}
G0 Z5
G0 X0 Y0
G1 Z<(-Depth)> F<(Feed / 3)>
G1 X40 F<Feed>
G1 Y25
G1 X0
G1 Y0
G0 Z5
M9
M5
M30
