function test_getfrsbf(src, flexmb)
% getfrsbf returns each listed variable with the documented shape (io/results.md), for one step
% and for all, from a static run (load steps 0..4: .sbd with dx and bigd, .sbm) and a kinematic
% run (mode 0, one step); names are case-insensitive; a bad step or name is an error.
  copyfile(fullfile(src, 'tools', 'tests', 'data', 'cantilever_static.dat'), 'cant.dat');
  spacar(-10, 'cant');
  sbd = 'cant.sbd'; sbm = 'cant.sbm';
  nx = getfrsbf(sbd, 'nx'); ne = getfrsbf(sbd, 'NE'); tdef = getfrsbf(sbd, 'tdef');
  ndof = getfrsbf(sbd, 'ndof'); nddof = getfrsbf(sbd, 'nddof');
  assert(isequal([nx ne tdef ndof nddof], [9 6 5 6 6]), 'counts');  % load steps 0..4
  nxp = getfrsbf(sbd, 'nxp'); nep = getfrsbf(sbd, 'nep');
  assert(isequal(size(nxp), [1 4]) && sum(nxp) == nx && isequal(size(nep), [1 4]) && sum(nep) == ne, 'nxp/nep');
  % Topology: as stored, with or without a step.
  topo = {'lnp', [103 2]; 'ln', [2 4]; 'le', [2 3]; 'it', [1 2]; 'rl0', [2 1]; 'rxyz', [0 0]};
  for k = 1:rows(topo)
    assert(isequal(size(getfrsbf(sbd, topo{k, 1})), topo{k, 2}), '%s shape', topo{k, 1});
    assert(isequal(getfrsbf(sbd, upper(topo{k, 1}), 2), getfrsbf(sbd, topo{k, 1})), '%s with a step', topo{k, 1});
  end
  rl0 = getfrsbf(sbd, 'rl0');
  assert(abs(rl0(1) - 0.5) < 1e-15 && abs(rl0(2) - 0.5) < 1e-15, 'rl0');
  % Per-step vectors: all steps tdef x n, one step n x 1, equal to that row.
  vecs = {'x', nx; 'xd', nx; 'xdd', nx; 'fxt', nx; 'e', ne; 'ed', ne; 'edd', ne; 'sig', ne};
  for k = 1:rows(vecs)
    all = getfrsbf(sbd, vecs{k, 1});
    assert(isequal(size(all), [tdef vecs{k, 2}]), '%s all steps: %s', vecs{k, 1}, mat2str(size(all)));
    one = getfrsbf(sbd, upper(vecs{k, 1}), 3);
    assert(isequal(size(one), [vecs{k, 2} 1]) && isequal(one, all(3, :).'), '%s step 3', vecs{k, 1});
  end
  % Per-step matrices: all steps tdef x (rows*cols), one step rows x cols.
  mats = {sbd, 'dx', [nx ndof]; sbd, 'bigd', [ne nx]; sbm, 'm0', [nddof nddof]; sbm, 'K0', [nddof nddof];
          sbm, 'g0', [nddof nddof]; sbm, 'n0', [nddof nddof]; sbm, 'c0', [nddof nddof]; sbm, 'D0', [nddof nddof]};
  for k = 1:rows(mats)
    all = getfrsbf(mats{k, 1}, mats{k, 2});
    sz = mats{k, 3};
    assert(isequal(size(all), [tdef prod(sz)]), '%s all steps: %s', mats{k, 2}, mat2str(size(all)));
    one = getfrsbf(mats{k, 1}, mats{k, 2}, 2);
    assert(isequal(size(one), sz) && isequal(reshape(all(2, :), sz), one), '%s step 2', mats{k, 2});
  end
  % SPACAR Light's use: K0 + G0 is the static stiffness; its inverse through dx gives the
  % compliance of the tip (the tip load's displacement over the load).
  K = getfrsbf(sbm, 'k0', tdef) + getfrsbf(sbm, 'g0', tdef);
  assert(norm(K - K.', 1) < 1e-9 * norm(K, 1), 'K0 + G0 not symmetric');
  % One stored step (mode 0): natural shapes without a step.
  spacar(-0, 'cant');
  assert(getfrsbf(sbd, 'tdef') == 1, 'mode 0 tdef');
  assert(isequal(size(getfrsbf(sbd, 'x')), [nx 1]), 'x with one step is a column');
  assert(isequal(size(getfrsbf(sbd, 'dx')), [nx ndof]), 'dx with one step is nx x ndof');
  assert(isequal(size(getfrsbf(sbd, 'bigd')), [ne nx]), 'bigd with one step');
  % Large arrays are written zlib-compressed (issue 38: a 64-element roll-up's .sbm went from 290 MB
  % to 34 MB): a chain of 24 PLBEAMs in 6 load steps, read back the same as the uncompressed ones.
  n = 24;
  t = '';
  for e = 1:n
    t = [t sprintf('PLBEAM %d %d %d %d %d\n', e, e, 100 + e, e + 1, 101 + e)];
  end
  for e = 1:n + 1
    t = [t sprintf('X %d %.17g 0\n', e, (e - 1) / n)];
  end
  t = [t 'FIX 1\nFIX 101\n'];
  for e = 1:n
    t = [t sprintf('DYNE %d 1 2 3\n', e)];
  end
  t = [t 'END\nHALT\n'];
  for e = 1:n
    t = [t sprintf('EM %d 0.3 1e-7\nESTIFF %d 8e6 2.8\n', e, e)];
  end
  t = [t sprintf('DELXF %d 0 -1\nITERSTEP 10 5\nEND\nEND\n', n + 1)];
  fid = fopen('chain.dat', 'w'); fprintf(fid, t); fclose(fid);
  spacar(-10, 'chain');
  m = 3 * n;
  K = getfrsbf('chain.sbm', 'k0', 6);
  assert(isequal(size(K), [m m]) && norm(K - K.', 1) < 1e-9 * norm(K, 1), 'compressed k0');
  assert(norm(getfrsbf('chain.sbm', 'c0', 6), 1) == 0, 'compressed zero c0');
  info = dir('chain.sbm');
  assert(info.bytes < 6 * 6 * m^2 * 8 / 3, 'chain.sbm is %d bytes: not compressed', info.bytes);
  % Errors.
  assertError(@() getfrsbf(sbd, 'nosuch'), 'nosuch');
  assertError(@() getfrsbf(sbd, 'x', 2), 'step must be an integer from 1 to 1');
  fprintf('getfrsbf: %d variables checked for one step and for all\n', rows(topo) + rows(vecs) + rows(mats) + 7);
end

function assertError(f, text)
  try
    f();
  catch err
    assert(~isempty(strfind(err.message, text)), 'error "%s" lacks "%s"', err.message, text);
    return;
  end
  error('no error raised (expected "%s")', text);
end
