" a full circle of radius 4 about (50, 50) with the 10 mm end mill: a disc of radius 9, 4 deep
N10 T1 G00 X50 Y50 Z5
N20 G01 Z-4 F200
N30 X54
N40 G02 X54 Y50 I-4 J0
N50 G01 X50
N60 G00 Z30
