; EXPECT 3:1 G803 is an implicit subroutine call
%P
G803
M30
