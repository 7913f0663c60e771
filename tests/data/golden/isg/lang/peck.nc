%peck (a modal cycle: down @P1 and back up, incrementally)
N10 G91 G01 Z[-@P1] F100
N20 Z[@P1]
N30 M17
