"EXPECT 8:5 G73 loops would execute 175,820,550 blocks (Q20 at line 3 inside Q20 at line 4 inside Q20 at line 5 inside Q20 at line 6 inside Q20 at line 7 inside Q20 at line 8), more than the limit of 1,000,000
N10 G01 X28. Z-1. F100
N20 G73 L10 Q20
N30 G73 L10 Q20
N40 G73 L10 Q20
N50 G73 L10 Q20
N60 G73 L10 Q20
N70 G73 L10 Q20
N80 G00 X40.
N90 M30
