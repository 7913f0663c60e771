; EXPECT 3:7 P7 is read before it is assigned
%P
G01 X[P7] F100
M30
