; EXPECT 3:1 V.P.DEPTH is not declared
%P
V.P.DEPTH = 3
M30
