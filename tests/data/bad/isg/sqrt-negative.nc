; EXPECT 3:6 SQRT[-1] has no value
%P
P1 = SQRT[-1]
M30
