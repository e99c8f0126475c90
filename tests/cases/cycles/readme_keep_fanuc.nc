%
O0001
G21 G90 G17
N1 (the README drilling program with a G82 dwell of P500 - ms on Fanuc - kept for Fanuc, P in ms)
N3 S1500.
N3 M3
N4 G0 X0. Y0. Z10.
N5 G98 G82 X10. Y10. Z-3. R2. P500 F120.
N6 G99 G83 X20. Y10. Z-12. R2. Q4.
N7 G99 G81 X25. Y10. Z-1. R2.
N7 G99 G81 X30. Y10. Z-1. R2.
N8 G80
N9 G0 Z10.
N10 M30
%
