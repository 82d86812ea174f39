function [time, sig, f] = flexmb_test_loads(t, ne, le, e, ep, nx, lnp, x, xp)
% USERSIG of arm_user.dat: a torque 0.3 cos(3t) in the elbow hinge (element 101) and a force
% 2 sin(5t) in y at the tip (node 3).
  time = t;
  sig = zeros(ne, 1);
  sig(le(101, 1)) = 0.3 * cos(3 * t);
  f = [3 2 2 * sin(5 * t)];
end
