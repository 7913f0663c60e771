; EXPECT 3:9 division by zero
%P
G01 X[1 / 0] F100
M30
