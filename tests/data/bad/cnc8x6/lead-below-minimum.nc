"EXPECT 3:15 below the smallest lead, 0.001 mm/rev
N10 M03 S100 X28. Z2.
N20 G33 Z-20. F0.0001
