; EXPECT 3:1 #TRAFO ON: a kinematic transformation is not modelled
%P
#TRAFO ON
G01 X1 F100
M30
