G21 G90 G17
N1 (G33.1: written as it is for linuxcnc and generic, absolute, K with two more decimals)
N3 S500. M3
N4 G0 X10. Y10. Z5.
N5 G33.1 Z-10. K1.25
N6 G33.1 Z-12. K1.25 I2.
N7 G33.1 Z2. K1.
N8 G33.1 Z1. K1.
N9 G0 X20.
N10 M30
