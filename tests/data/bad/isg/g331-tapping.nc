; EXPECT 4:5 G331 on a mill is not modelled by the simulator
%P
N10 G00 X10 Y10 Z5
N20 G331 Z-10 K1.5 S200
N30 M30
