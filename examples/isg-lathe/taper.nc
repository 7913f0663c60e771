%TAPER (taper thread 1:10 on the radius, lead 2 along Z, two passes)
N10 G51                           ;diameter programming
N15 T1 D1 M03 S300                ;tool, spindle clockwise
N20 G00 X44 Z3                    ;approach
N25 G01 X30.8 F600                ;first pass, 0.4 mm (radially) above the final one
N30 G33 X36.8 Z-27 K2             ;under 45 degrees: the lead is given along Z (K)
N35 G00 X44                       ;retract out of the undercut
N40 Z3                            ;back to the start height
N45 G01 X30                       ;final pass
N50 G33 X36 Z-27 K2
N55 G00 X44
N60 M05 X100 Z100                 ;end position
N65 M30                           ;end of program
