"EXPECT 2:9 tool number T1.5 must be a whole number
N10 G00 T1.5 X28. Z2.
