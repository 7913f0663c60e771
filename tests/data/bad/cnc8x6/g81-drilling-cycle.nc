"EXPECT 3:5 G81 (a drilling cycle, which the CNC8x6 manual does not describe
N10 G00 X0 Z5.
N20 G81 Z-10. F0.1
N30 M30
