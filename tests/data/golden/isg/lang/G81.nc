%G81 (the implicit call behind G81 on this test machine: down @P1 at F50, up to @P2 above that)
N10 G91 G01 Z[-@P1] F50
N20 G00 Z[@P2]
N30 M17
