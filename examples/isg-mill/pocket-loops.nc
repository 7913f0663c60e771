%pocket (a 30 x 20 pocket 4 mm deep at the G54 origin, cleared by loops)
#VAR
  V.P.ROWS = 4                             ; zig-zag rows per level
  V.P.X0 = 3                               ; tool centre rectangle: pocket minus the 3 mm radius
  V.P.X1 = 27
  V.P.Y0 = 3
  V.P.Y1 = 17
#ENDVAR
N10 G17 G90 G54 T1 M06
N20 M03 S8000 F600
N30 G00 X[V.P.X0] Y[V.P.Y0] Z2
N40 $FOR P1 = 1, 2, 1                      ; two levels of 2 mm
N50   G01 Z[-2 * P1] F200
N60   P2 = 0                               ; row index
N70   $WHILE P2 < V.P.ROWS                 ; rows 14 / 3 = 4.667 mm apart (less than the 6 mm tool)
N80     P3 = V.P.Y0 + P2 * [V.P.Y1 - V.P.Y0] / [V.P.ROWS - 1]
N90     G01 Y[P3] F600
N100    $IF P2 MOD 2 == 0
N110      G01 X[V.P.X1]
N120    $ELSE
N130      G01 X[V.P.X0]
N140    $ENDIF
N150    P2 = P2 + 1
N160  $ENDWHILE
N170  LL CONTOUR                           ; the walls, round the tool centre rectangle
N180  G00 Z2
N190  G00 X[V.P.X0] Y[V.P.Y0]
N200 $ENDFOR
N210 G00 Z20
N220 M05
N230 M30

%L CONTOUR
N300 G01 Y[V.P.Y0]
N310 X[V.P.X1]
N320 Y[V.P.Y1]
N330 X[V.P.X0]
N340 M29
