G21 G90 G17
N1 (arc centres put on a coarser grid than the input's: --decimals 3)
N2 (rounding start, end and centre apart can turn an arc; of the grid)
N3 (points around the centre, the one closest to the exact arc is printed)
N5 G0 X0. Y0. Z1.
N6 G1 Z-1. F100.
N7 G0 X-22.556 Y-15.841
N8 G2 X-21.768 Y-16.626 I-0.135 J-0.923
N9 G0 X40.535 Y-15.821
N10 G3 X43.809 Y-19. I2.477 J-0.725
N11 G0 X30.359 Y41.6
N12 G2 X29.391 Y41.921 I-0.484 J0.16
N13 G0 Z1.
N14 M30
