"EXPECT 3:15 greater than zero
N10 M03 S100 X28. Z2.
N20 G33 Z-20. F0 I0.
