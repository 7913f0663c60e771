; EXPECT 3:1 G41 (tool radius compensation) is not modelled
%P
G41 G01 X10 F100
M30
