; EXPECT 3:1 G23 (mirroring on X and Y)
%P
G23
M30
