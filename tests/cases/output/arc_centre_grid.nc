G21 G90 G17
N1 (arc centres on the output grid, 4 decimals here)
N2 (given on the grid, with equal radii: printed as given)
N4 G0 X0. Y0. Z1.
N5 G1 Z-1. F100.
N6 G2 X10. Y0. I5. J0.
N7 G3 X4.5 Y5.5 I-2.5 J3.
N8 (on the grid, but the end radius 0.002 shorter than the start's: a)
N9 (slight spiral, printed as given, as rs274 cuts it)
N10 G1 X0. Y0.
N11 G2 X10. Y0. I5.001 J0.
N12 (off the grid in mm, after a unit switch: the nearest grid point)
N14 G1 X15.24 Y5.08
N15 G3 X15.8648 Y5.08 I0.3124 J0.
N17 G0 Z1.
N18 M30
