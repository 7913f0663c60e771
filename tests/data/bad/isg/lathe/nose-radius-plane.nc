; EXPECT 5:5 tool nose radius compensation works in the turning plane (G18, ZX)
%t
N10 G17
N15 G00 X28 Z2
N20 G42 G01 Z-20 F100
N30 M30
