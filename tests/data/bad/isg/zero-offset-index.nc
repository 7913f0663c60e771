; EXPECT 4:1 V.G.NP[7]: the zero offsets are V.G.NP[1] (G54) .. V.G.NP[6] (G59)
%P
G01 X1 F100
V.G.NP[7].V.X = 10
G59 X2
M30
