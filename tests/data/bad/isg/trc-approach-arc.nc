; EXPECT 4:1 the approach block of tool radius compensation must be a straight move
%P
G00 Z-1
G41 G02 X10 Y0 I5 J0 F100
G01 Y20
G40 X0
M30
