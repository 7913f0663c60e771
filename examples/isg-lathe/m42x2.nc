%L thread_pass
N100 G33 Z-33 K2                  ;cut one pass of the thread, lead 2 along Z
N110 G00 X48                      ;retract out of the undercut
N120 Z5                           ;back to the start height
N130 M29                          ;end of subprogram

%M42X2 (thread depth 1.227 mm)
N10 G51                           ;diameter programming
N15 T1 D1 M03 S300                ;tool, spindle clockwise
N20 G00 X48 Z5                    ;approach
N25 G01 X41.1 F800                ;depth of cut 1
N30 LL thread_pass
N35 G01 X40.4                     ;depth of cut 2
N40 LL thread_pass
N45 G01 X39.9                     ;depth of cut 3
N50 LL thread_pass
N55 G01 X39.546                   ;final depth: 42 - 2 * 0.6134 * 2
N60 LL thread_pass
N65 G01 X39.546                   ;same depth again: spring pass
N70 LL thread_pass
N75 M05 X120 Z150                 ;to the end position
N80 M30                           ;end of program
