G21 G90 G17
N1 (the fit stage: chords of a quarter circle and of a helix, a corner)
N3 G0 X10. Y0. Z2.
N4 G1 Z-1. F300.
N5 G3 X0. Y10. I-10. J0. (fit: 18 moves, lines 5-22)
N23 G1 X-5.
N24 G3 X-13.66 Y5. Z-1.6 I0.001 J-10.001 (fit: 12 moves, lines 24-35)
N36 G0 Z2.
N37 M30
