%
(M20x1.5 external thread by one G76 block: compound infeed, degression, a spring pass and)
(tapers at both ends, inside a 20 mm bar - LinuxCNC 2.9)
G21 G18 G7 G90 G94 G40 G80       (mm, XZ plane, X is a diameter: so are G76's I, J and K)
T1 M6                            (60 degree threading tool)
S300 M3                          (G76 needs the spindle turning)
G0 X22 Z5                        (above the bar)
Z-4                              (the drive line: diameter 22 at Z-4, where the thread begins)
(P1.5: pitch. I-2: crest 2 below the drive line in diameter, 20. K1.8402: thread depth)
(0.6134 * 1.5 = 0.9201, root diameter 18.1598. J0.6 R2: pass n at depth 0.3 * sqrt[n])
(radius below the crest. Q29.5: compound infeed. H1: one spring pass. E2 L3: tapers 2 mm)
(long at both ends)
G76 P1.5 Z-30 I-2 J0.6 R2 K1.8402 Q29.5 H1 E2 L3
G0 X40 Z40
M5
M2
%
