function test_spacar_options(src, flexmb)
% spacar(mode, name, opts): the integrator and its settings from Octave (issue 23). The stiff damped
% probe (datfiles/tests/damped_probe.dat) with opts.integrator 'bdf', 'auto' and 'galpha' equals a
% tight-tolerance BDF reference and the Kelvin-Voigt creep law of its tip; tend / intervals set the
% span and the output grid; bad options are usage errors. Ctrl-C (SIGINT to Octave) during a run,
% inside flexmb and inside a user function, stops it with the identifier flexmb:spacar:interrupted
% after the steps so far were written to the .sbd and assigned (tdef says how many), and Octave and
% the gateway go on working. Timings are printed, not asserted.
  copyfile(fullfile(src, 'datfiles', 'tests', 'damped_probe.dat'), '.');
  copyfile(fullfile(src, 'tools', 'octave', 'tests', 'data', 'rod_user.dat'), 'rod_slow.dat');
  t0 = tic;
  b = spacar(-1, 'damped_probe', struct('integrator', 'bdf'));
  tb = toc(t0);
  t0 = tic;
  a = spacar(-1, 'damped_probe', struct('Integrator', 'auto'));
  ta = toc(t0);
  g = spacar(-1, 'damped_probe', struct('integrator', 'galpha', 'rhoinf', 0.5));
  r = spacar(-1, 'damped_probe', struct('integrator', 'bdf', 'reltol', 1e-9, 'abstol', 1e-16, 'bdforder', 5));
  assert(b.tdef == 101 && a.tdef == 101 && r.tdef == 101 && g.tdef == 101, 'steps: %d %d %d %d', b.tdef, a.tdef, ...
         r.tdef, g.tdef);
  tip = b.lnp(3, 2);
  yr = r.x(:, tip);
  db = max(abs(b.x(:, tip) - yr)) / abs(yr(end));
  da = max(abs(a.x(:, tip) - yr)) / abs(yr(end));
  EI = 1.031e-2;
  ys = 0.1 * 0.01^3 / (3 * EI);
  creep = ys * (1 - exp(-r.time(2:end) / (1e-3 / EI)));
  dr = max(abs(yr(2:end) - creep) ./ creep);
  fprintf('damped probe: bdf %.3f s, auto %.3f s; vs reference (bdf order 5, RelTol 1e-9): bdf %.2e, auto %.2e; reference vs creep law %.2e\n', ...
          tb, ta, db, da, dr);
  dg = max(abs(g.x(:, tip) - yr)) / abs(yr(end));
  assert(db < 1e-3 && da < 1e-3 && dg < 1e-3, 'bdf / auto / galpha differ from the reference by %g / %g / %g', ...
         db, da, dg);
  assert(dr < 1e-2, 'the reference differs from the creep law by %g', dr);
  % tend and intervals.
  c = spacar(-1, 'damped_probe', struct('integrator', 'bdf', 'tend', 0.002, 'intervals', 4));
  assert(c.tdef == 5 && abs(c.time(end) - 0.002) < 1e-15, 'tend / intervals: %d steps to %g', c.tdef, c.time(end));
  % Bad options.
  bad = {struct('integrator', 'rk4'), struct('reltol', -1), struct('intervals', 1.5), struct('bdforder', 6), ...
         struct('stepsize', 1), struct('integrator', 'galpha', 'rhoinf', 1.5), 3};
  for k = 1:numel(bad)
    try
      spacar(-1, 'damped_probe', bad{k});
      error('option set %d was accepted', k);
    catch err
      assert(strcmp(err.identifier, 'flexmb:spacar:usage'), 'option set %d: %s (%s)', k, err.message, err.identifier);
    end
  end
  try
    spacar(-10, 'damped_probe', struct('integrator', 'bdf'));
    error('statics took integrator options');
  catch err
    assert(strcmp(err.identifier, 'flexmb:spacar:usage'), '%s', err.message);
  end
  % Ctrl-C inside flexmb: an ode45 run of the probe over 0.1 ms takes about half a minute (steps of
  % ~3e-11 s; the default, auto, would switch to galpha and finish); its outputs are 1e-8 s apart.
  interrupt('damped_probe', struct('integrator', 'ode45', 'tend', 1e-4, 'intervals', 10000));
  % Ctrl-C while Octave runs a user function (20 ms per call).
  interrupt('rod_slow', struct('tend', 100, 'intervals', 100000), 'flexmb_test_slow_loads');
  d = spacar(-1, 'damped_probe', struct('integrator', 'bdf'));
  assert(isequal(d.x, b.x), 'the gateway differs after the interrupts');
  % opts.target (issue 32): the guidance reduced with the smallest modal basis meeting 1e-2, against
  % the full run in the same measure (every position, of the motion).
  copyfile(fullfile(src, 'datfiles', 'straight_guidance.dat'), '.');
  full = spacar(-1, 'straight_guidance');
  red = spacar(-1, 'straight_guidance', struct('target', 1e-2));
  assert(red.tdef == full.tdef, 'output times: %d against %d', red.tdef, full.tdef);
  pos = reshape(full.lnp(full.lnp(:, 2) > 0, 1:2), [], 1);  % planar position nodes: x and y
  motion = max(max(abs(full.x(:, pos) - full.x(1, pos))));
  err = max(max(abs(red.x(:, pos) - full.x(:, pos)))) / motion;
  fprintf('opts.target 1e-2 on the guidance: error %.3g of the motion\n', err);
  assert(err <= 1e-2, 'opts.target 1e-2: the reduced run is %g off', err);
  % Issue 36: an oversized run is refused as on the command line (here: a maximum step that needs
  % more than 1e9 steps), before anything runs.
  try
    spacar(-1, 'straight_guidance', struct('maxstep', 1e-12));
    error('the oversized run was accepted');
  catch err
    assert(strcmp(err.identifier, 'flexmb:spacar:input') && ~isempty(strfind(err.message, 'steps (the limit is')), ...
           '%s (%s)', err.message, err.identifier);
  end
  for bad = {0, 1, -1, 'x'}
    try
      spacar(-1, 'straight_guidance', struct('target', bad{1}));
      error('target %s was accepted', num2str(bad{1}));
    catch err
      assert(strcmp(err.identifier, 'flexmb:spacar:usage'), '%s (%s)', err.message, err.identifier);
    end
  end
end

function interrupt(name, opts, usersig)
  if nargin > 2
    text = fileread([name '.dat']);
    text = strrep(text, 'USERSIG flexmb_test_fis_loads', ['USERSIG ' usersig]);
    fid = fopen([name '.dat'], 'w');
    fprintf(fid, '%s', text);
    fclose(fid);
  end
  system(sprintf('(sleep 2; kill -INT %d) >/dev/null 2>&1 &', getpid()));
  t0 = tic;
  try
    spacar(-1, name, opts);
    error('%s: not interrupted', name);
  catch err
    elapsed = toc(t0);
    assert(strcmp(err.identifier, 'flexmb:spacar:interrupted'), '%s: %s (%s)', name, err.message, err.identifier);
  end
  assert(elapsed < 20, '%s: the interrupt took %.1f s', name, elapsed);
  % The workspace (this function's) got the steps so far, and the file holds the same.
  assert(exist('tdef', 'var') == 1 && exist('x', 'var') == 1, '%s: no tdef / x in the workspace', name);
  assert(tdef >= 1 && size(x, 1) == tdef, '%s: tdef %d, x %d rows', name, tdef, size(x, 1));
  xs = getfrsbf([name '.sbd'], 'x');
  assert(getfrsbf([name '.sbd'], 'tdef') == tdef && isequal(reshape(xs, size(x)), x), ...
         '%s: the .sbd differs from the workspace', name);
  fprintf('%s: interrupted after %.2f s: %s\n', name, elapsed, err.message);
end
