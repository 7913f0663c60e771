; EXPECT 3:1 tool centre point control (RTCP) is not modelled
%P
#RTCP ON
M30
