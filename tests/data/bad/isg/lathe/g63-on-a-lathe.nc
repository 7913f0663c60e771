; EXPECT 4:5 G63 on a lathe (tapping with the spindle following the path
%t
N10 G00 X0 Z5
N20 G63 Z-10 F300 S200
N30 M30
