%vars (variables, parameters, subprograms)
#VAR
  V.P.DEPTH = 2
  V.P.XS[3] = [10, 20, 30]
  V.L.STEP = 5
#ENDVAR
N10 G90 T1 M06 M03 S1000 F300
N20 P1 = V.E.PASSES                 ; 3, from the setup
N30 $FOR P2 = 0, P1 - 1, 1
N40   G01 X[V.P.XS[P2]] Y[V.L.STEP] Z[-V.P.DEPTH]
N50 $ENDFOR
N60 V.P.DEPTH = V.P.DEPTH + 1
N70 LL SLOT                         ; its own V.L.STEP (7) does not change the caller's
N80 G01 Y[V.L.STEP * 2]             ; 10: the main program's V.L.STEP is still 5
N90 $IF V.E.MODE == "FINISH"
N100  G00 Z[V.G.SAFE_Z]             ; 25
N110 $ENDIF
N120 M30

%L SLOT
#VAR
  V.L.STEP = 7
#ENDVAR
N200 G01 X[V.P.XS[2] + V.L.STEP] Z[-V.P.DEPTH]  ; X37 Z-3
N210 M29
