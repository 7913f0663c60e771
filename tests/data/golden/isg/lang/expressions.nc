%expr (operators and functions of [ ] expressions)
N10 G90 T1 M06 M03 S1000 F300
N20 G01 X[2 + 3 * 4] Y[[2 + 3] * 4] Z-1       ; 14, 20: point before dash
N30 G01 X[2 ** 3] Y[11 MOD 3]                 ; 8, 2
N40 G01 X[SIN[30] * 10] Y[COS[60] * 10]       ; 5, 5 (degrees)
N50 G01 X[SQRT[16] + SQR[3]] Y[ABS[-7]]       ; 4 + 9 = 13, 7
N60 G01 X[INT[-2.7] + 10] Y[FRACT[2.75] * 4]  ; -2 + 10 = 8, 0.75 * 4 = 3
N70 G01 X[ROUND[2.5]] Y[ATAN2[1, 1]]          ; 3, 45
N80 G01 X[TAN[45] * 20] Y[EXP[0] + LN[1]]     ; 20, 1
N90 P1 = 6
N100 G01 X[P1 / 4] Y[-P1]                     ; 1.5, -6
N110 $IF P1 > 5 AND P1 < 7 && NOT [P1 == 7]
N120   G01 X50
N130 $ENDIF
N140 $IF P1 < 5 OR P1 == 6
N150   G01 Y50
N160 $ENDIF
N170 G01 X 52.5 Y 10 ( a space between address and value, a comment to the end of the line
N180 M30
