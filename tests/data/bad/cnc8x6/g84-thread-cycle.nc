"EXPECT 3:5 G84 (the thread cutting cycle the manual names but does not describe
N10 G00 X0 Z5.
N20 G84 Z-10. F1.5
N30 M30
