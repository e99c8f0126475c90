G21 G90 G17
N1 (Issue 48: a pocket lap's lower edge is at Y 38.3875 computed two ways)
N2 ( 38.38749999… and 38.38750000… ; it prints the same, Y38.388, at both)
N3 (ends: ties at the last decimal round half away from zero, and a value)
N4 (within 1e-9 of a tie is the tie.)
N8 G0 X50. Y40. Z5.
N9 G0 X45.975
N9 G1 Z0. F200.
N9 G1 Z-3.
N9 G1 X54.025 F600.
N9 G1 X45.975
N9 G1 X44.363 Y38.388
N9 G1 X55.638
N9 G1 Y41.613
N9 G1 X44.363
N9 G1 Y38.388
N9 G1 X42.75 Y36.775
N9 G1 X57.25
N9 G1 Y43.225
N9 G1 X42.75
N9 G1 Y36.775
N9 G1 X45.975 Y40.
N9 G0 Z5.
N9 G0 X50.
N10 M30
