function test_user_functions(src, flexmb)
% USERINP / USERSIG called back into Octave during spacar(1, ...) with SPACAR's conventions as
% FlexibleInstrumentSimulation (FIS) uses them: vectors passed as rows, USERINP returning rows
% [node comp value rate accel] (and [element def ...]) with `is` ignored, USERSIG returning f rows
% [node comp value], Euler-parameter components 1-4 included. The arm driven by MATLAB functions
% (crank motion; elbow torque and tip force) equals the same arm written with flexmb's time
% expressions (INPUTET, ESIGT, XFT) to 1e-12; a spatial rod with functions written the way FIS
% writes its own equals its time-expression twin, and fx / fxtot hold what the user applied and
% the input force. A user function that throws, or returns the wrong shape, ends the run with a
% message naming the function and the time, keeps the steps stored so far (files and workspace),
% and leaves Octave working. The command line refuses the file for simulate, check accepts it.
  data = fullfile(src, 'tools', 'octave', 'tests', 'data');
  copyfile(fullfile(data, 'arm_expr.dat'), '.');
  copyfile(fullfile(data, 'arm_user.dat'), '.');
  copyfile(fullfile(data, 'rod_expr.dat'), '.');
  copyfile(fullfile(data, 'rod_user.dat'), '.');
  rod(flexmb);
  a = spacar(-1, 'arm_expr');
  t0 = tic;
  b = spacar(-1, 'arm_user');
  fprintf('arm_user: spacar(1) with USERINP + USERSIG in %.2f s, %d steps, %d evaluations\n', toc(t0), ...
          b.nsteps, b.nfevals);
  assert(isequal(size(a.x), size(b.x)) && a.tdef == 101, 'arm: step counts differ');
  worst = 0;
  for v = {'time', 'x', 'xd', 'xdd', 'e', 'ed', 'edd', 'sig', 'fxt'}
    d = max(max(abs(a.(v{1}) - b.(v{1}))));
    scale = max(1, max(max(abs(a.(v{1})))));
    assert(d <= 1e-12 * scale, 'arm: %s differs by %g (scale %g)', v{1}, d, scale);
    worst = max(worst, d / scale);
  end
  % The driven hinge follows the user's motion; the elbow carries the user's torque plus its spring.
  assert(max(abs(b.e(:, b.le(100, 1)) - 0.5 * sin(2 * b.time))) < 1e-10, 'crank motion not followed');
  sigElbow = 5.0 * b.e(:, b.le(101, 1)) + 0.3 * cos(3 * b.time);
  assert(max(abs(b.sig(:, b.le(101, 1)) - sigElbow)) < 1e-9, 'elbow torque');
  assert(max(abs(b.fxt(:, b.lnp(3, 2)) - 2 * sin(5 * b.time))) < 1e-12, 'tip force not in fxt');
  fprintf('arm: USERINP/USERSIG equal the time expressions to %.3g (relative, worst variable)\n', worst);

  % A throwing user function: a MATLAB error naming function and time; results so far kept.
  txt = fileread('arm_user.dat');
  writeFile('arm_fail.dat', strrep(txt, 'USERSIG flexmb_test_loads', 'USERSIG flexmb_test_failing_loads'));
  clear x tdef
  try
    spacar(-1, 'arm_fail');
    error('no error from a failing USERSIG');
  catch err
    assert(~isempty(strfind(err.message, 'flexmb_test_failing_loads')), 'message lacks the function: %s', err.message);
    assert(~isempty(regexp(err.message, 't = 0\.3', 'once')), 'message lacks the time: %s', err.message);
    assert(~isempty(strfind(err.message, 'tip sensor lost')), 'message lacks the reason: %s', err.message);
    assert(isempty(strfind(err.message, 'step size')), 'message blames the step size: %s', err.message);
    fprintf('failing USERSIG: "%s"\n', err.message);
  end
  assert(exist('tdef', 'var') == 1 && tdef >= 30 && tdef < 101, 'results so far not in the workspace');
  assert(getfrsbf('arm_fail.sbd', 'tdef') == tdef, 'results so far not in arm_fail.sbd');
  assert(max(abs(x(end, :) - a.x(tdef, :))) < 1e-12, 'kept steps differ from the full run');
  % Wrong shape.
  writeFile('arm_shape.dat', strrep(txt, 'USERSIG flexmb_test_loads', 'USERSIG flexmb_test_wrong_shape'));
  try
    spacar(-1, 'arm_shape');
    error('no error from a USERSIG of the wrong shape');
  catch err
    assert(~isempty(strfind(err.message, 'flexmb_test_wrong_shape')) && ~isempty(strfind(err.message, 'returned sig of size')), ...
           'wrong-shape message: %s', err.message);
    assert(~isempty(regexp(err.message, 't = 0\.5', 'once')), 'message lacks the time: %s', err.message);
    fprintf('wrong shape: "%s"\n', err.message);
  end
  % A missing user function.
  writeFile('arm_missing.dat', strrep(txt, 'USERSIG flexmb_test_loads', 'USERSIG no_such_function_here'));
  try
    spacar(-1, 'arm_missing');
    error('no error from a missing USERSIG function');
  catch err
    assert(~isempty(strfind(err.message, 'no_such_function_here')), 'missing-function message: %s', err.message);
  end
  % Octave still works, and the gateway too.
  c = spacar(-1, 'arm_user');
  assert(isequal(c.x, b.x), 'a second run differs');
  % The command line refuses USERSIG / USERINP with a pointer to spacar() (input error, exit 1);
  % mode 0 (check) does not call them and accepts the file with a note.
  [status, out] = system(sprintf('"%s" simulate arm_user.dat -q 2>&1', flexmb));
  assert(status == 1 && ~isempty(strfind(out, 'spacar()')) && ~isempty(strfind(out, 'arm_user.dat:')), ...
         'command line: status %d, %s', status, out);
  [status, out] = system(sprintf('"%s" check arm_user.dat 2>&1', flexmb));
  assert(status == 0 && ~isempty(strfind(out, 'USERSIG flexmb_test_loads')) && ~isempty(strfind(out, 'spacar()')), ...
         'check: status %d, %s', status, out);
end

% The spatial rod: FIS-shaped user functions against time expressions; fx, fxtot, lnp.
function rod(flexmb)
  % ode45: its steps are a function of the right-hand sides alone, so the two runs agree to round-off
  % (the default, auto, runs galpha here, whose Newton iterations carry the round-off up to RelTol).
  ode45 = struct('integrator', 'ode45');
  a = spacar(-1, 'rod_expr', ode45);
  b = spacar(-1, 'rod_user', ode45);
  assert(b.tdef == 41 && isequal(size(a.x), size(b.x)), 'rod: %d steps', b.tdef);
  assert(size(b.lnp, 2) == 4, 'rod: lnp has %d columns, SPACAR''s spatial lnp has 4', size(b.lnp, 2));
  worst = 0;
  for v = {'x', 'xd', 'xdd', 'e', 'ed', 'sig', 'fxt', 'fx'}
    d = max(max(abs(a.(v{1}) - b.(v{1}))));
    scale = max(1, max(max(abs(a.(v{1})))));
    assert(d <= 1e-10 * scale, 'rod: %s differs by %g (scale %g)', v{1}, d, scale);
    worst = max(worst, d / scale);
  end
  % The base follows USERINP; fx holds exactly what USERSIG applied at the stored states (recomputed
  % here from the stored x by FIS's formula), nothing elsewhere; fxtot is fxt (the workspace name).
  t = b.time;
  assert(max(abs(b.x(:, b.lnp(5, 1)) - (-0.1 + 0.02 * sin(4 * t)))) < 1e-12, 'rod: base motion not followed');
  assert(max(abs(b.xd(:, b.lnp(5, 1)) - 0.08 * cos(4 * t))) < 1e-12, 'rod: base rate not followed');
  F = [zeros(size(t)), 0.2 * sin(5 * t), 0.1 * cos(3 * t)];
  assert(max(max(abs(b.fx(:, b.lnp(1, 1:3)) - F))) < 1e-14, 'rod: fx at the tip is not the USERSIG force');
  for k = 1:numel(t)
    q = b.x(k, b.lnp(2, :));
    qt = [0 -q(4) q(3); q(4) 0 -q(2); -q(3) q(2) 0];
    T = 2 * [q(1) -q(2:4); q(2:4)' q(1) * eye(3) - qt] * [0; 0.01; 0; 0.02];
    assert(max(abs(b.fx(k, b.lnp(2, :)) - T')) < 1e-14, 'rod: fx on the Euler parameters at step %d', k);
  end
  others = setdiff(1:b.nx, [b.lnp(1, 1:3), b.lnp(2, :)]);
  assert(all(all(b.fx(:, others) == 0)), 'rod: fx has loads where USERSIG put none');
  assert(all(all(b.fxgrav == 0)), 'rod: fxgrav without gravity');
  assert(isequal(b.fxtot, b.fxt), 'rod: the workspace fxtot is not fxt');
  clear fxtot fx
  spacar(-1, 'rod_user', ode45);
  assert(exist('fxtot', 'var') == 1 && isequal(fxtot, b.fxt) && isequal(fx, b.fx), 'rod: workspace fxtot / fx');
  % The input force: the axial reaction fxtot at the pushed coordinate carries the rod.
  fin = b.fxtot(:, b.lnp(5, 1));
  assert(all(isfinite(fin)) && max(abs(fin)) > 0, 'rod: no input force in fxtot');
  fprintf('rod: FIS-shaped USERINP/USERSIG equal the time expressions to %.3g; fx, fxtot as applied\n', worst);
end

function writeFile(path, text)
  fid = fopen(path, 'w');
  fputs(fid, text);
  fclose(fid);
end
