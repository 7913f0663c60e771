; EXPECT 3:1 [machine] m_functions
%P
M151
M30
