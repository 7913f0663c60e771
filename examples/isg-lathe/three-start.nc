%THREE_START (lead 4.5 mm, three starts 120 degrees apart, thread depth 0.92 mm)
N10 G51                           ;diameter programming
N15 T1 D1 M03 S250                ;tool, spindle clockwise
N20 G00 X40 Z4                    ;approach
N25 G01 X34.16 F800               ;thread depth: 36 - 2 * 0.92
N30 G33 Z-24 K4.5                 ;first start, offset 0
N35 G00 X40                       ;retract out of the undercut
N40 Z4                            ;back to the start height
N45 G01 X34.16
N50 G33 Z-24 K4.5 S.OFFSET=120    ;second start, 120 degrees later
N55 G00 X40
N60 Z4
N65 G01 X34.16
N70 G33 Z-24 K4.5 S.OFFSET=240    ;third start, 240 degrees later
N75 G00 X40
N80 M05 X100 Z100                 ;end position
N85 M30                           ;end of program
