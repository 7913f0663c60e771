; EXPECT 5:1 a rotation or mirroring changed while tool radius compensation is active
%P
G41 G01 X10 Y0 F100
X20
G22
X30
M30
