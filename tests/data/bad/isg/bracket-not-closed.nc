; EXPECT 3:13 expected to close the
%P
G01 X[1 + 2 F100
M30
