function [time, sig, f] = flexmb_test_fis_loads(t, ne, le, e, ep, nx, lnp, x, xp)
% USERSIG of data/rod_user.dat, written the way FlexibleInstrumentSimulation writes its contact
% function (FFESFVA): x and xp are indexed as rows through lnp, an orientation node's four Euler
% parameters as x(lnp(node, :)), a moment turned into generalised forces on them with
% T = 2 Q(q) [0; M] and returned as rows [node component value], components 1-4. Loads: a force
% (0, 0.2 sin 5t, 0.1 cos 3t) on the tip node 1 and the global moment (0.01, 0, 0.02) on its
% orientation node 2. Checks the shapes SPACAR passes (rows; lnp with 4 columns) on every call.
  if ~(isrow(x) && isrow(xp) && numel(x) == nx && numel(xp) == nx && isrow(e) && isrow(ep) && numel(e) == ne)
    error('USERSIG got x %s, xp %s, e %s (expected rows of %d and %d)', mat2str(size(x)), mat2str(size(xp)), ...
          mat2str(size(e)), nx, ne);
  end
  if size(lnp, 2) ~= 4
    error('USERSIG got lnp with %d columns (expected 4 in a spatial model)', size(lnp, 2));
  end
  node = 1;
  q = x(lnp(node + 1, :));
  qp = xp(lnp(node + 1, :));
  qtilde = [0 -q(4) q(3); q(4) 0 -q(2); -q(3) q(2) 0];
  Q_bar = [q(1) -q(2:4); q(2:4)' q(1) * eye(3) - qtilde];
  omega = 2 * Q_bar' * qp';  % angular velocity (global), as FFESFVA computes it: needs qp as a row
  if abs(omega(1)) > 1e-6 * max(1, norm(omega))
    error('USERSIG: the Euler parameters and their rates are not consistent (omega_0 = %g)', omega(1));
  end
  F = [0, 0.2 * sin(5 * t), 0.1 * cos(3 * t)];
  M_o = [0.01, 0, 0.02];
  T_bar = 2 * Q_bar * [0; M_o'];
  f = [node 1 F(1); node 2 F(2); node 3 F(3); ...
       node + 1 1 T_bar(1); node + 1 2 T_bar(2); node + 1 3 T_bar(3); node + 1 4 T_bar(4)];
  sig = [];
  time = t;
end
