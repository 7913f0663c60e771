; EXPECT 3:10 G351 Y2: the value is -1 (mirroring on) or 1 (off)
%P
G351 X-1 Y2
M30
