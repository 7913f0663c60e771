; EXPECT 3:1 rotation
%P
#CS ON [0, 0, 0, 0, 0, 30]
M30
