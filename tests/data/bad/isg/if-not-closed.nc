; EXPECT 3:1 $IF is not closed
%P
$IF 1 == 1
G01 X1 F100
M30
