"EXPECT 5:5 G73 loops would execute 18,015,006 blocks (Q2000 at line 4 inside Q3000 at line 5)
N10 G01 X28. Z-1. F100
N20 Z-2.
N30 G73 L10 Q2000
N40 G73 L20 Q3000
N50 M30
