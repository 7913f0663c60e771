%pocket_sub (a square of side @P1 about the current point at depth @P2)
N10 G91 G01 Z[@P2 - 2]
N20 X[@P1] 
N30 Y[@P1]
N40 X[-@P1]
N50 Y[-@P1]
N60 Z[2 - @P2]
N70 G90
N80 M29
