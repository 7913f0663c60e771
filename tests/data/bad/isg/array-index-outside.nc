; EXPECT 6:1 index outside the array
%P
#VAR
V.P.A[3] = [1, 2, 3]
#ENDVAR
V.P.A[3] = 4
M30
