; EXPECT 3:25 division by zero
%P
#ROTATION ON [ANGLE = 1 / 0]
M30
