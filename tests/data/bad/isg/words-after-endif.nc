; EXPECT 4:8 must stand alone
%P
$IF 1
$ENDIF G01 X1
M30
