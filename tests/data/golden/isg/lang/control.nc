%control (control structures)
N10 G90 G17 T1 M06 M03 S1000 F300
N20 P1 = 0
N30 $WHILE P1 < 3                  ; three passes: X0, X10, X20
N40   G01 X[P1 * 10] Y5 Z-1
N50   P1 = P1 + 1
N60 $ENDWHILE
N70 $FOR P2 = 1, 4, 1              ; P2 = 1, 2, 3, 4
N80   $IF P2 == 2
N90     $CONTINUE                  ; no move for P2 = 2
N100  $ELSEIF P2 >= 4
N110    $BREAK                     ; leaves the loop at P2 = 4
N120  $ELSE
N130    G01 Y[P2 * 10]             ; Y10 (P2 = 1), Y30 (P2 = 3)
N140  $ENDIF
N150 $ENDFOR
N160 $SWITCH P2                    ; P2 is 4 after the $BREAK
N170 $CASE 3
N180   G01 X33
N190 $CASE 4
N200   G01 X44                     ; runs, and falls through to $CASE 5
N210 $CASE 5
N220   G01 X55
N230   $BREAK
N240 $DEFAULT
N250   G01 X66
N260 $ENDSWITCH
N270 P3 = 0
N280 $DO                           ; body once at least: Z-2, Z-3
N290   P3 = P3 + 1
N300   G01 Z[-1 - P3]
N310 $ENDDO P3 < 2
N320 $IF P3 == 2 $GOTO [DONE]      ; jumps over the X99 move
N330 G01 X99
N340 [DONE]
N350 $GOTO N370
N360 G01 X98                       ; jumped over
N370: G00 Z10
N380 M30
