%global (a global subprogram file with call parameters)
N10 G90 T1 M06 M03 S1000 F300
N20 G00 X10 Y10 Z2
N30 L CYCLE [NAME = pocket_sub.nc @P1 = 4 @P2 = -1.5]
N40 L pocket_sub [@P1 = 2, @P2 = -3]
N50 G00 Z20
N60 M30
