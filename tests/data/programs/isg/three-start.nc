%DREI (three starts, lead 3 mm, pitch 1 mm, depth 0.6 mm)
N10 G51                           ;diameters
N15 T1 D1 M03 S200
N20 G00 X32 Z15
N25 G01 X28.8 F500
N30 G33 Z-2 K3 S.OFFSET=0         ;1st start
N35 G00 X32
N40 Z15
N45 G01 X28.8
N50 G33 Z-2 S.OFFSET 120          ;2nd start: lead K3 is modal, '=' is optional
N55 G00 X32
N40 Z15
N45 G01 X28.8
N50 G33 Z-2 S.OFFSET=240          ;3rd start
N55 G00 X32
N60 M05 X60 Z40
N65 M30
