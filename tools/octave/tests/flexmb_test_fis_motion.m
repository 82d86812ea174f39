function [t, e, x5] = flexmb_test_fis_motion(t, is)
% USERINP of data/rod_user.dat, written the way FlexibleInstrumentSimulation writes its insertion
% motion (FFESMVA): is is ignored, e is [], and the one input coordinate (node 5, x) comes as a row
% [node component position velocity acceleration]: x = -0.1 + 0.02 sin 4t.
  e = [];
  x5 = [5 1 -0.1 + 0.02 * sin(4 * t), 0.08 * cos(4 * t), -0.32 * sin(4 * t)];
end
