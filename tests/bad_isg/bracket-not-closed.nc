; EXPECT 3:13 ] expected
%P
G01 X[1 + 2 F100
M30
