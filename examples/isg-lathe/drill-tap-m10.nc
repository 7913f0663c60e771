%DRILLTAP (centre drill, drill 8.5 through, tap M10x1.5 through)
N10 G51                           ;diameter programming
N15 T1 D1 M03 S1200               ;centre drill 5 / 12.5, 90 degree countersink
N20 G00 X0 Z3
N25 G01 Z-9 F60                   ;countersink to 11 at the face: tip 6 + 3 deep
N30 G00 Z3
N35 T2 D2 S800                    ;twist drill 8.5, 118 degree point
N40 G01 Z-19 F80                  ;through: full diameter down to Z-16.45
N45 G00 Z3
N50 M05
N55 T3 D3                         ;tap M10x1.5
N60 G331 Z-20 K1.5 S200           ;right-hand thread, the spindle following the tap
N65 G332 Z3                       ;back out along the same helix, the spindle reversed
N70 G00 X80 Z50                   ;end position
N75 M30
