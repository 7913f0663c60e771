; EXPECT 4:14 below the programming resolution, 0.0001 mm
%thread
N10 M03 S100 G00 X16 Z2
N20 G33 Z-20 K0.00001
N30 M30
