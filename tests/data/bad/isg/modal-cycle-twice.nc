; EXPECT 5:17 cycle call while the modal cycle cyc (line 3) is active
%P
L CYCLE [NAME = cyc MODAL_MOVE]
X10
L CYCLE [NAME = cyc MODAL]
M30
