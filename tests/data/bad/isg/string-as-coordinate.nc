; EXPECT 3:5 is the string "abc", not a number
%P
G01 X["abc"] F100
M30
