G21 G90 G17
N1 (DEBUG and PRINT: notes with the parameters' values; MSG: a comment)
N5 (DEBUG, depth=#<depth> count=#1 unset=#<nothing>)
N6 (print, #1 passes)
N7 (MSG, check the clamp)
N10 (DEBUG, pass #2)
N10 (DEBUG, pass #2)
N10 (DEBUG, pass #2)
N13 G0 X3. Z-1.25
N14 M30
