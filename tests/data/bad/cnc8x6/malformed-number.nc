"EXPECT 2:10 malformed number
N10 G00 X28.0.1 Z2.
