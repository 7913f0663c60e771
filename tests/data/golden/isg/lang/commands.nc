%cmds (# commands, work offsets, G92, machine functions, extra axes)
N10 G90 T1 M06 M03 S1000 F300
N20 #MSG ["start"]
N30 #FLUSH WAIT
N40 #HSC [BSPLINE PATH_DEV 0.2]
#COMMENT BEGIN
G01 X999 (never read)
#COMMENT END
N50 G54 G00 X0 Y0                   ; G54 = (10, 20, 0): machine (10, 20)
N60 G01 Z-1
N70 G55 G01 X0 Y0                   ; G55 = (50, 50, -5): (50, 50); Z not programmed, stays -1
N80 G53 G00 Z10                     ; offsets off: Z10
N90 #CS ON [5, 5, 0, 0, 0, 0]       ; a translation: X1 -> 6
N100 G00 X1 Y1
N110 #CS OFF
N120 G00 X1 Y1
N130 G92 X5 Y5                      ; reference point offset (5, 5), added to the programmed values
N140 G00 X10 Y10                    ; machine (15, 15)
N150 M200=40 H7 M110                ; machine functions from the setup
N160 G01 A90 X20                    ; A is tracked; X20 -> 25
N170 M30
