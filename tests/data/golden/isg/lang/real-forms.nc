% wall test 1 (a title written without parentheses, as a bioprinter's translator does)
N10 L vendor_start.nc             ; the machine's start program: declared external, nothing runs
N20 G92 G90 X100 Y50 Z10          ; reference point offset (100, 50, 10)
N30: G00 X0 Y0 Z0 C90             ; machine (100, 50, 10); C is tracked
N40  #VAR
N50  V.P.LAYER[2] = [1, 0.5]
N60  #ENDVAR
N70  "ARC_ON"                     ; a macro the start program defines: declared external
N80: G01 X[10 * V.P.LAYER[0]] F500
N90: Z[V.P.LAYER[1]]
N100 "ARC_OFF"
N110 #VAR
N120 V.P.LAYER[2] = [2, 1.5]
N130 #ENDVAR
N140: G01 X[10 * V.P.LAYER[0]]
N150: Z[V.P.LAYER[1]]
N160 V.G.NP[1].V.X = 200          ; the zero offset table: G54 is V.G.NP[1]
N170 V.G.NP[1].V.Y = -V.G.NP[1].V.X / 4
N180 G92 X0 Y0 Z0
N190 G54 G01 X1 Y1
N200 V.G.NP_AKT.V.Z = -10         ; the active zero offset, at once
N210 Z5
N220 M30
