%COMP (tool radius compensation and a circle given by its radius)
N10 G17 G00 X-10 Y-10 Z2
N20 G01 Z-1 F200
N30 G41 X0 Y0          ; approach (G139, indirect)
N40 Y20
N50 G02 X20 Y20 R10    ; half circle about (10, 20)
N60 G01 Y0
N70 X0
N80 G40 X-10 Y-10      ; departure
N90 G00 Z10
N100 M30
