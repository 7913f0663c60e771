; EXPECT 3:3 global subprogram 'NOTHERE.nc'
%P
L NOTHERE.nc
M30
