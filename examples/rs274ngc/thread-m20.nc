%
(M20x1.5 external thread on a lathe: G33 passes from an O-word loop, LinuxCNC 2.9)
G21 G18 G7 G90 G94 G40 G80       (mm, XZ plane, X is a diameter, absolute)
T1 M6                            (60 degree threading tool, tool table entry 1)
S400 M3                          (spindle clockwise: G33 needs it turning)
#<major> = 20
#<pitch> = 1.5
#<root> = [#<major> - 2 * 0.6134 * #<pitch>]   (thread depth 0.6134 * pitch: root 18.1598)
#<x> = [#<major> - 0.6]
G0 X24 Z5                        (start of every pass: Z5, so all passes share one groove)
o100 while [#<x> gt #<root>]
  G1 X#<x> F200                  (infeed)
  G33 Z-23 K#<pitch>             (one pass, 1.5 mm per revolution along Z)
  G0 X24                         (out)
  Z5                             (back to the start)
  #<x> = [#<x> - 0.5]
o100 endwhile
o110 repeat [2]                  (the final depth twice: the second is a spring pass)
  G1 X#<root> F200
  G33 Z-23 K#<pitch>
  G0 X24
  Z5
o110 endrepeat
M5
G0 X60 Z60
M2
%
