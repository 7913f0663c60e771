; EXPECT 4:1 G41 under G237 (perpendicular selection/deselection of tool radius compensation)
%P
G237
G41 G01 X10 Y10 F100
G40 X0
M30
