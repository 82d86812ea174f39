function test_spacar_modes(src, flexmb)
% spacar modes 3, 4, 9, 10 and 0 give what the command line gives (--mode 3, --mode 4, transfer,
% static): the same files byte for byte (.sbd, .sbm, .ltv) and so the same variables; the example
% script runs. (Mode 1: test_spacar_paper.)
  copyfile(fullfile(src, 'datfiles', 'slider_crank_s95.dat'), 'sc.dat');
  copyfile(fullfile(src, 'tools', 'tests', 'data', 'cantilever_static.dat'), 'cant.dat');
  copyfile(fullfile(src, 'datfiles', 'spatial', 'cross_spring_pivot_transfer.dat'), 'pivot.dat');
  mkdir('cli');
  cases = {3, 'sc', '--mode 3 sc.dat --out cli/sc -q', {'.sbd', '.sbm'};
           4, 'sc', '--mode 4 sc.dat --out cli/sc -q', {'.sbd', '.sbm'};
           9, 'pivot', 'transfer pivot.dat --no-bode --out cli/pivot -q', {'.sbd', '.sbm', '.ltv'};
           10, 'cant', 'static cant.dat --out cli/cant_static.csv', {'.sbd', '.sbm'}};
  for k = 1:rows(cases)
    [mode, name, args, exts] = cases{k, :};
    [status, out] = system(sprintf('"%s" %s', flexmb, args));
    assert(status == 0, 'flexmb %s: %s', args, out);
    r = spacar(-mode, name);
    for ext = exts
      assert(isequal(flexmb_test_bytes(fullfile('cli', [name ext{1}])), flexmb_test_bytes([name ext{1}])), ...
             'mode %d: %s%s is not the bytes flexmb %s writes', mode, name, ext{1}, args);
      cli = load(fullfile('cli', [name ext{1}]), '-mat');
      own = load([name ext{1}], '-mat');
      for v = fieldnames(cli)'
        assert(isequal(own.(v{1}), cli.(v{1})), 'mode %d: %s%s differs from flexmb %s', mode, v{1}, ext{1}, args);
      end
    end
    assert(r.mode == mode && isfield(r, 'M0') && isfield(r, 'freq'), 'mode %d: struct lacks M0 / freq', mode);
    fprintf('mode %d: %s%s the bytes of flexmb %s (%d steps, M0 %s)\n', mode, name, strjoin(exts, ', '), args, ...
            r.tdef, mat2str(size(r.M0)));
  end
  r = spacar(-0, 'cant');
  assert(r.mode == 0 && isequal(size(r.dx), [r.nx r.ndof]) && isequal(size(r.bigd), [r.ne r.nx]), 'mode 0');
  % bigd * dx = de/dq: identity on the dynamic deformation rows (all of cant's deformations are DYNE).
  D = r.bigd * r.dx;
  assert(norm(D - eye(r.ne), 1) < 1e-12, 'mode 0: bigd * dx is not the identity on the DYNE deformations');
  try
    spacar(2, 'cant');
    error('mode 2 accepted');
  catch err
    assert(~isempty(strfind(err.message, 'not supported')) && strcmp(err.identifier, 'flexmb:spacar:mode'), err.message);
    assert(~isempty(strfind(err.message, 'setpoint')) && ~isempty(strfind(err.message, 'mode 1')), err.message);
  end
  % Nothing of a refused mode reaches the workspace or a file (no silent partial answer).
  clear x;
  if exist('cant2.sbd', 'file'), delete('cant2.sbd'); end
  copyfile('cant.dat', 'cant2.dat');
  try
    r2 = spacar(-2, 'cant2');
    error('mode -2 accepted');
  catch err
    assert(strcmp(err.identifier, 'flexmb:spacar:mode'), err.identifier);
  end
  assert(exist('x', 'var') == 0 && exist('r2', 'var') == 0 && ~exist('cant2.sbd', 'file'), 'mode 2 left results');
  try
    spacar(1, 'cant_missing');
    error('missing file accepted');
  catch err
    assert(strcmp(err.identifier, 'flexmb:spacar:input'), err.identifier);
  end
  run(fullfile(src, 'tools', 'octave', 'examples', 'guidance_example.m'));
  assert(exist('u', 'var') == 1 && max(abs(u)) > 0.05, 'example: no motion');
end
