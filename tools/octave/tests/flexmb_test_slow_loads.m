function [time, sig, f] = flexmb_test_slow_loads(t, ne, le, e, ep, nx, lnp, x, xp)
% USERSIG of the Ctrl-C test (test_spacar_options.m): the FIS-shaped loads of flexmb_test_fis_loads,
% 20 ms per call, so that an interrupt most likely arrives while Octave runs the user function.
  pause(0.02);
  [time, sig, f] = flexmb_test_fis_loads(t, ne, le, e, ep, nx, lnp, x, xp);
end
