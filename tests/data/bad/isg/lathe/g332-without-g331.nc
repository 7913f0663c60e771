; EXPECT 4:5 G332 backs out the tap from where a G331 stopped
%t
N10 G00 X0 Z5
N20 G332 Z10 K1.5
N30 M30
