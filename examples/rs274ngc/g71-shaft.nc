%
(A stepped shaft roughed by G71 and finished by G70 from one profile, in a 30 mm bar - LinuxCNC 2.9)
G21 G18 G7 G90 G94 G40 G80       (mm, XZ plane, X is a diameter: so is every X of the profile)
T1 M6                            (93 degree turning tool, sharp tip)
S1200 M3
F150
o100 sub                         (the finished profile, from the face outwards)
  G1 X12 Z0                      (its start P0: diameter 12 at the face)
  G1 Z-10                        (diameter 12 for 10 mm)
  G1 X20 Z-14                    (a 45 degree taper up to diameter 20)
  G1 Z-22                        (diameter 20 for 8 mm)
  G3 X26 Z-25 K-3                (a convex quarter round of radius 3 about Z-25 up to diameter 26)
  G1 Z-32                        (diameter 26 up to a square shoulder at Z-32)
  G1 X31                         (out past the bar)
o100 endsub
G0 X32 Z2                        (the cycle's start S)
G71 Q100 D0.2 I1.5 R0.5          (rough: passes 1.5 deep in radius, 0.2 left on the profile)
G70 Q100 X32 Z2                  (finish on the profile)
G0 X40 Z40
M5
M2
%
