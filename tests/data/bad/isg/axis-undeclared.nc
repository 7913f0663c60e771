; EXPECT 3:13 [machine] axes
%P
G01 X1 F100 B45
M30
