"EXPECT 2:5 parameter number R100 is outside R00..R99
N10 R100=1.0
N20 G00 X28. Z2.
