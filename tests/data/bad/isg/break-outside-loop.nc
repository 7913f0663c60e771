; EXPECT 3:1 $BREAK outside a loop
%P
$BREAK
M30
