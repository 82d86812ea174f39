function [t, e, x] = flexmb_test_crank(t, is)
% USERINP of arm_user.dat in SPACAR's form (as FlexibleInstrumentSimulation's FFESMVA): one row
% [element deformation value rate acceleration] per input deformation; the shoulder hinge
% (element 100, the only input) turns as 0.5 sin(2t). is is not used; there is no input coordinate.
  e = [100 1 0.5 * sin(2 * t) cos(2 * t) -2 * sin(2 * t)];
  x = [];
end
