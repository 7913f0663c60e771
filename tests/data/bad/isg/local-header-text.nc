; EXPECT 2:9 unexpected text after the program name
%L SUB1 first pass
G01 X1 F100
M29
%P
LL SUB1
M30
