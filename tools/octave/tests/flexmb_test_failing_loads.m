function [time, sig, f] = flexmb_test_failing_loads(t, ne, le, e, ep, nx, lnp, x, xp)
% A USERSIG that fails after t = 0.3 (for the error test).
  if t > 0.3
    error('tip sensor lost at %.3f', t);
  end
  [time, sig, f] = flexmb_test_loads(t, ne, le, e, ep, nx, lnp, x, xp);
end
