; EXPECT 3:1 macro "LAYER" is not defined
%P
"LAYER"
M30
