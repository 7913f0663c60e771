; EXPECT 3:1 #WIBBLE is not known
%P
#WIBBLE ON
M30
