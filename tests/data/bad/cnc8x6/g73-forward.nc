"EXPECT 3:9 G73 jumps back; N40 comes after this block
N10 G01 X28. Z-1. F100
N20 G73 L40 Q2
N30 Z-2.
N40 Z-3.
