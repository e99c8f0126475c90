G21 G90 G17
$H
N2 (grbl homing: the file is a grbl program, its dwell in seconds)
N4 S12000. M3
N5 G4 P10.
N6 G0 X0. Y0. Z5.
N7 M30
