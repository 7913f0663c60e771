(A 40 x 40 boss 5 mm high, profiled with cutter radius compensation G42: the program)
(gives the boss's own outline; the 10 mm end mill runs 5 mm outside it, round each corner)
G21 G17 G90 G94 F400
T1 M6
G43
S3000 M3
G0 X-45 Y-45 Z5
G42 D1
G0 X-20 Y-35          (entry above the stock: ends 5 mm right of this point, on the line y = -25)
G1 Z-5                (down where the tool stands)
G1 X-20 Y-20 F400     (along the left side to the first corner, then round the boss)
G1 X20
G1 Y20
G1 X-20
G1 Y-20
G1 X-10
G0 Z5
G40
G0 X-45 Y-45
M5
M2
