; EXPECT 4:12 circle radius R5 is too small for the distance 20.0000
%P
G01 X0 Y0 F100
G02 X20 Y0 R5
M30
