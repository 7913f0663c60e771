; EXPECT 5:1 a circle in the plane ZX under a coordinate system rotated about Z
%P
#CS ON [10, 0, 0, 0, 0, 30]
G18 G01 X10 Z-1 F100
G02 X20 Z-1 I5 K0
M30
