function test_spacar_overconstrained(src, flexmb)
% spacar(0) of an overconstrained model (two beams in series between two clamps, every deformation
% DYNE, so the second beam repeats the 6 constraints the first already puts on the middle node)
% does not fail: it stores the initial configuration and bigd, which is how SPACAR Light
% (tools/octave/README.md) finds overconstraints: the rank deficiency of bigd's rows of fixed,
% input and dynamic deformations on the calculable coordinates is 6, and no coordinate is free.
  fid = fopen('twobeams.dat', 'w');
  fprintf(fid, 'BEAM 1 1 2 3 4 0 1 0\nBEAM 2 3 4 5 6 0 1 0\nX 1 0 0 0\nX 3 0.5 0 0\nX 5 1 0 0\n');
  fprintf(fid, 'FIX 1\nFIX 2\nFIX 5\nFIX 6\nDYNE 1 1 2 3 4 5 6\nDYNE 2 1 2 3 4 5 6\nEND\nHALT\nEND\nEND\n');
  fclose(fid);
  warning('off', 'flexmb:spacar:kinematics');
  r = spacar(-0, 'twobeams');
  assert(r.mode == 0 && r.tdef == 1, 'mode 0: one step');
  assert(~isfield(r, 'dx'), 'mode 0 of an overconstrained model: dx is not defined');
  nep = getfrsbf('twobeams.sbd', 'nep');
  nxp = getfrsbf('twobeams.sbd', 'nxp');
  D = getfrsbf('twobeams.sbd', 'bigd', 1);
  assert(isequal(size(D), [r.ne r.nx]), 'bigd is ne x nx');
  Dcc = D(1:(nep(1) + nep(3) + nep(4)), nxp(1) + (1:nxp(2)));
  s = svd(Dcc);
  rk = sum(s > sqrt(eps) * s(1));
  assert(rk == nxp(2), 'calculable coordinates left free: rank %d of %d', rk, nxp(2));
  assert(rows(Dcc) - rk == 6, 'overconstraints: %d, expected 6', rows(Dcc) - rk);
  x = getfrsbf('twobeams.sbd', 'x');
  lnp = getfrsbf('twobeams.sbd', 'lnp');
  assert(isequal(x(lnp(3, 1:3)).', [0.5 0 0]), 'initial coordinates of the middle node');
  printf('overconstrained: bigd %dx%d, calculable block %dx%d of rank %d (6 overconstraints)\n', ...
         size(D), size(Dcc), rk);
end
