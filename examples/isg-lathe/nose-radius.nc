%NOSE (a chamfer, a taper and a shoulder turned on the contour with nose radius compensation)
N10 G51                           ;diameter programming
N15 T1 D1 M03 S1000               ;CNMG 120408: 80 degree rhombus, nose radius 0.8, hand R
N20 G00 X12 Z6                    ;above the chamfer's start
N30 G42 G01 Z2 F200               ;compensation right of the travel: outside, towards the chuck
N40 X20 Z-2                       ;45 degree chamfer
N50 Z-20                          ;diameter 20
N60 X30 Z-30                      ;taper, the radius rising 1 in 2
N70 Z-40                          ;diameter 30
N80 G40 X40                       ;up the shoulder face at Z-40, compensation off
N90 G00 X60 Z50                   ;end position
N95 M30
