%STEEP_TAPER (taper thread at 51.3 degrees to the axis: the lead is given along X)
N10 G51                           ;diameter programming
N15 T1 D1 M03 S60                 ;tool, spindle clockwise
N20 G00 X4 Z60                    ;above the top of the cone
N25 G01 Z47.6 F500                ;start of the thread, clear of the stock
N30 G33 X68 Z22 I3                ;radius 2 -> 34 while Z falls 25.6: 45 degrees or more, lead on I
N35 G00 Z60                       ;up, clear of the bar (radius 34 > 30)
N40 M05 X100 Z100                 ;end position
N45 M30                           ;end of program
