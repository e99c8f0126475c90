G21 G90 G17
N1 (An R a few microns short of half the chord is the half circle about its middle, with one warning)
N4 G0 X0. Y0. Z5.
N5 G1 Z-1. F300.
N6 G2 X10. Y0. I5. J0.
N7 G3 X20. Y0. I5. J0.
N8 M30
