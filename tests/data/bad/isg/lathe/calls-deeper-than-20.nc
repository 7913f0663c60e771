; EXPECT 60:8 local subprograms nested more than 20 deep
%L sub1
N10 LL sub2
N20 M29
%L sub2
N10 LL sub3
N20 M29
%L sub3
N10 LL sub4
N20 M29
%L sub4
N10 LL sub5
N20 M29
%L sub5
N10 LL sub6
N20 M29
%L sub6
N10 LL sub7
N20 M29
%L sub7
N10 LL sub8
N20 M29
%L sub8
N10 LL sub9
N20 M29
%L sub9
N10 LL sub10
N20 M29
%L sub10
N10 LL sub11
N20 M29
%L sub11
N10 LL sub12
N20 M29
%L sub12
N10 LL sub13
N20 M29
%L sub13
N10 LL sub14
N20 M29
%L sub14
N10 LL sub15
N20 M29
%L sub15
N10 LL sub16
N20 M29
%L sub16
N10 LL sub17
N20 M29
%L sub17
N10 LL sub18
N20 M29
%L sub18
N10 LL sub19
N20 M29
%L sub19
N10 LL sub20
N20 M29
%L sub20
N10 LL sub21
N20 M29
%L sub21
N10 G01 X14 F100
N20 M29
%main
N10 LL sub1
N20 M30
