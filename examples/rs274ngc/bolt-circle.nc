%
(Six holes on a bolt circle by an O-word loop with G81, a deep centre hole with G83, LinuxCNC 2.9)
G21 G17 G90 G94 G40 G49 G80 G54  (mm, XY plane, absolute, work offset G54 at the plate centre)
T1 M6
G43                              (tool length from the tool table)
S3000 M3
F300
G0 Z10
#<i> = 0
o100 while [#<i> lt 6]
  #<a> = [#<i> * 60]             (every 60 degrees)
  G99 G81 X[20 * cos[#<a>]] Y[20 * sin[#<a>]] R2 Z-5
  #<i> = [#<i> + 1]
o100 endwhile
G80
G98 G83 X0 Y0 R2 Z-12 Q3         (centre hole, pecks of 3 mm)
G80 G0 Z50
M5
M30
%
