"EXPECT 5:5 the Z position -100000.1000 exceeds the permitted range
N10 G01 X28. Z2. F100
N20 G91 Z-50000.
N30 Z-50000.
N40 Z-2.1
