; EXPECT 3:9 Z-1000000000000: value exceeds the permitted range
%move
N10 G01 Z-1000000000000 F100
N20 M30
