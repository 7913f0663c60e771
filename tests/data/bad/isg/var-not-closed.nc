; EXPECT 5:1 #VAR at line 3 is not closed by #ENDVAR
%P
#VAR
V.P.A = 1
M30
