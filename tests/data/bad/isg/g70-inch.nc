; EXPECT 3:1 G70 (inch programming) is not modelled
%P
G70
M30
