; EXPECT 4:1 a change of the compensation side without G40
%P
G41 G01 X10 F100
G42 X20
M30
