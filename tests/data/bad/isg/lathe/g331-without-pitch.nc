; EXPECT 4:5 G331 without a pitch: program it on K, signed
%t
N10 G00 X0 Z5
N20 G331 Z-10 S200
N30 M30
