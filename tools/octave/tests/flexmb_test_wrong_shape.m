function [time, sig, f] = flexmb_test_wrong_shape(t, ne, le, e, ep, nx, lnp, x, xp)
% A USERSIG that returns sig of the wrong size after t = 0.5 (for the error test).
  [time, sig, f] = flexmb_test_loads(t, ne, le, e, ep, nx, lnp, x, xp);
  if t > 0.5
    sig = sig(1:end - 1);
  end
end
