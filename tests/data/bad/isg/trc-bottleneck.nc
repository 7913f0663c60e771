; EXPECT 6:1 the tool radius 3 does not fit the arc of radius 2
%P
G00 X10 Y0 Z-1
G42 G01 X20 Y0 F100
Y20
G02 X24 Y20 I2 J0
G01 Y0
G40 X30
M30
