; EXPECT 3:1 unexpected $ENDIF
%P
$ENDIF
M30
