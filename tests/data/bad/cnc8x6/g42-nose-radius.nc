"EXPECT 3:5 G42 (tool nose radius compensation, which the CNC8x6 manual does not describe
N10 G00 X28. Z2.
N20 G42 G01 Z-20. F0.1
N30 M30
