G21 G90 G17
N1 (Ger's entry: straight to where the first move's offset path starts, here X-3 Y-10, not rs274's X-3 Y-8.146 after a corner)
N4 T1 M6
N5 S10000. M3
N6 G0 X-20. Y-20. Z5.
N7 G1 Z-2. F300.
N8 G1 X-3. Y-10. F500.
N9 G1 Y40.
N10 G2 X0. Y43. I3. J0.
N10 G1 X40.
N11 G2 X43. Y40. I0. J-3.
N11 G1 Y0.
N12 G2 X40. Y-3. I-3. J0.
N12 G1 X0.
N13 G1 X-5.
N14 G1 X-20. Y-20.
N15 G0 Z5.
N16 M30
