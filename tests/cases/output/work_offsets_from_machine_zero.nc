G21 G90 G17
N1 (G10 L2 gives machine coordinates. G55 set before the program selects a system goes to the machine, and is then folded into G54's terms: that takes the machine's G54 to be at machine zero, which ger cannot know, so it says so, once. G54 set and then folded after a selection likewise. G56 set by G10 L20 where the tool is measured from the tool, not from machine zero: no warning)
N3 G10 L2 P2 X100. Y50. Z0.
N4 G54
N5 G0 X110. Y60. Z10.
N7 G0 X120.
N10 G0 X6. Y6.
N13 G0 X8. Y8.
N14 M30
