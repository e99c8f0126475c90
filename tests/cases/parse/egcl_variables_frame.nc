(Frame and centre bore around a point, EGCL style with ; endings)
SetUnits("mm")
CenX = 50
CenY = 40
HalfW = 30
HalfH = 20
Rad = 10
Zsafe = 5
Depth = (-2.5)
FeedXY = 600
FeedZ = 150
G21
G90
G17
T1
M6
S9000
M3
G0 Z<Zsafe>
(outer frame)
G0 X<(CenX - HalfW)> Y<(CenY - HalfH)>
G1 Z<Depth> F<FeedZ>
G1 X<(CenX + HalfW)> F<FeedXY>
G1 Y<(CenY + HalfH)>
G1 X<(CenX - HalfW)>
G1 Y<(CenY - HalfH)>
G0 Z<Zsafe>
(centre bore: one full circle)
G0 X<(CenX + Rad)> Y<CenY>
G1 Z<Depth> F<FeedZ>
G3 X<(CenX + Rad)> Y<CenY> I<(-Rad)> J0 F<FeedXY>
G0 Z<Zsafe>
M5
M30
