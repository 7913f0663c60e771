" a straight groove with the 6 mm ball mill, tip 2 below the top
N10 T2 G00 X-10 Y50 Z-2
N20 G01 X110 F300
N30 G00 Z30
