G21 G90 G17
N1 (A wizard after canned cycles starts where they left the tool: over the)
N2 (last hole, at the G98 level  the second Drill's first hole is X30, the)
N3 (first's last, not X10, its first .)
N7 G0 X10. Y10. Z5.
N8 G98 G81 X10. Y10. Z-2. R1. F100.
N8 G98 G81 X20. Y10. Z-2. R1.
N8 G98 G81 X30. Y10. Z-2. R1.
N8 G80
N9 G0 Z5.
N9 G0 X30. Y10.
N9 G98 G81 X30. Y10. Z-2. R1.
N9 G98 G81 X35. Y10. Z-2. R1.
N9 G80
N10 M30
