function [t, e, x] = flexmb_test_crank(t, is)
% USERINP of arm_user.dat: the shoulder hinge (the only input deformation) turns as 0.5 sin(2t);
% is = 0, 1, 2 asks for the angle, its rate, its acceleration.
  switch is
    case 0
      e = 0.5 * sin(2 * t);
    case 1
      e = cos(2 * t);
    otherwise
      e = -2 * sin(2 * t);
  end
  x = [];
end
