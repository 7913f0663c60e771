; EXPECT 3:6 unknown function FOO
%P
P1 = FOO[2]
M30
