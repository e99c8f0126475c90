(Hole row on a plate, using every operator: + - * / % ^ unary -, comparisons, && || !)
Width = 90
Height = 60
Holes = 7
Margin = (2 ^ 3)
(8)
Tower = (2 ^ (3 ^ 2))
(2 ^ (3 ^ 2) = 512 if ^ is right-associative)
NegSq = (-(2 ^ 2))
(-(2 ^ 2) = -4 if ^ binds tighter than unary minus)
Pitch = ((Width - (2 * Margin)) / (Holes - 1))
Odd = ((Holes % 2) == 1)
Square = (Width == Height)
Wide = ((Width > Height) && (Width >= (2 * Height)))
Tall = ((Height > Width) || (Height >= (2 * Width)))
Small = ((Width * Height) < 5000)
Fits = ((Width <= 100) && (Height <= 100))
Plain = ((!Odd) || (!(Wide != Tall)))
Mid = ((-(-Height)) / 2)
(30)
Cnt = 0
G21
G90
G17
T1
M6
S3000
M3
G0 Z5
if (Fits && (!Small)) {
    while (Cnt < Holes) {
        G0 X<(Margin + (Cnt * Pitch))> Y<Mid>
        G1 Z-3 F100
        G0 Z5
        Cnt = (Cnt + 1)
    }
} else if (Square || Plain) {
    G0 X<(Width / 2)> Y<(Height / 2)>
    G1 Z-3 F100
    G0 Z5
}
M5
M30
