; EXPECT 6:1 a full circle cannot be programmed with its radius R
%P
G17 G00 X0 Y0 Z5
G01 Z-1 F100
G02 X10 Y0 R5
G03
M30
