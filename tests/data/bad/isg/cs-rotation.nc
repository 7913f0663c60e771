; EXPECT 3:1 rotation about Y by 30 degrees
%P
#CS ON [0, 0, 0, 0, 30, 0]
M30
