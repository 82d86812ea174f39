function test_user_functions(src, flexmb)
% USERINP / USERSIG called back into Octave during spacar(1, ...): the arm driven by MATLAB
% functions (crank motion; elbow torque and tip force) equals the same arm written with flexmb's
% time expressions (INPUTET, ESIGT, XFT) to 1e-12. A user function that throws, or returns the
% wrong shape, ends the run with a message naming the function and the time, keeps the steps
% stored so far (files and workspace), and leaves Octave working. The command line refuses the file.
  data = fullfile(src, 'tools', 'octave', 'tests', 'data');
  copyfile(fullfile(data, 'arm_expr.dat'), '.');
  copyfile(fullfile(data, 'arm_user.dat'), '.');
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
  % The command line refuses USERSIG / USERINP with a pointer to spacar() (input error, exit 1).
  [status, out] = system(sprintf('"%s" simulate arm_user.dat -q 2>&1', flexmb));
  assert(status == 1 && ~isempty(strfind(out, 'spacar()')) && ~isempty(strfind(out, 'arm_user.dat:')), ...
         'command line: status %d, %s', status, out);
end

function writeFile(path, text)
  fid = fopen(path, 'w');
  fputs(fid, text);
  fclose(fid);
end
