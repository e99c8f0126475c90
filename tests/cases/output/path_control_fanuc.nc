%
O0001
G21 G90 G17
N1 (Path control on Fanuc: G61.1 is its G61, its G64 has no P or Q: one warning)
N3 G64
N4 G1 X10. F300.
N5 G61
N6 G1 Y10.
N7 G61
N8 G1 X0.
N9 M30
%
