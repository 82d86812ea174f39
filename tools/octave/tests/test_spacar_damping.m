function test_spacar_damping(src, flexmb)
% spacar(mode, name, opts) with the damping a designer states (issue 53 item 4): a mass 4 on a
% spring 400 (w = 10 rad/s). Mode 1 with opts.rayleigh [0 beta] is a time run with EDAMP = beta *
% ESTIFF: the same x as the file with EDAMP beta k, the step response of zeta = beta w / 2. Mode 9
% with opts.dampingratio zeta puts -2 zeta w into A's damping entry, with opts.rayleigh [alpha beta]
% -(alpha + beta k / m). A modal ratio or alpha in a time run, damping in mode 10 or mode 3 on a
% static file, and integration options in mode 9 are errors that say why.
  body = 'PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2 2\nDYNE 1 1\nEND\nHALT\nESTIFF 1 400\n';
  write_file('step.dat', [body 'XM 2 4\nXF 2 0.001 0\nTIMESTEP 2 200\nEND\nEND\n']);
  write_file('step_edamp.dat', [body 'EDAMP 1 1.6\nXM 2 4\nXF 2 0.001 0\nTIMESTEP 2 200\nEND\nEND\n']);
  write_file('tf.dat', [body 'XM 2 4\nITERSTEP 10 1\nEND\nHALT\nINPUTF 1 2 1\nOUTX 1 2 1\nEND\nEND\n']);
  o = struct('integrator', 'ode45', 'reltol', 1e-10, 'abstol', 1e-15);
  o.rayleigh = [0 0.004];
  b = spacar(-1, 'step', o);
  e = spacar(-1, 'step_edamp', rmfield(o, 'rayleigh'));
  col = b.lnp(2, 1);
  xs = 1e-3 / 400; w = 10; zeta = 0.004 * w / 2; wd = w * sqrt(1 - zeta^2);
  t = b.time;
  exact = 1 + xs * (1 - exp(-zeta * w * t) .* (cos(wd * t) + zeta / sqrt(1 - zeta^2) * sin(wd * t)));
  dEdamp = max(abs(b.x(:, col) - e.x(:, col)));
  dExact = max(abs(b.x(:, col) - exact));
  fprintf('mode 1, rayleigh [0 0.004]: against EDAMP 1.6 %.1e, against the closed form %.1e of F/k\n', ...
          dEdamp / xs, dExact / xs);
  assert(numel(t) == 201 && dEdamp < 1e-12 * xs && dExact < 1e-6 * xs, 'mode 1 with rayleigh');
  spacar(-9, 'tf', struct('dampingratio', 0.02));
  [A, ~, ~, ~] = getss('tf');
  assert(abs(A(2, 2) + 2 * 0.02 * w) < 1e-12 * w && abs(A(2, 1) + w^2) < 1e-12 * w^2, 'mode 9 ratio: %s', mat2str(A));
  spacar(-9, 'tf', struct('rayleigh', [0.7 0.003]));
  [A, ~, ~, ~] = getss('tf');
  assert(abs(A(2, 2) + 0.7 + 0.003 * 400 / 4) < 1e-12, 'mode 9 rayleigh: %s', mat2str(A));
  spacar(-9, 'tf');
  [A, ~, ~, ~] = getss('tf');
  assert(A(2, 2) == 0, 'mode 9 undamped: %s', mat2str(A));
  flexmb_test_refused(@() spacar(-1, 'step', struct('dampingratio', 0.02)), 'flexmb:spacar:input', 'no form in a nonlinear time run');
  flexmb_test_refused(@() spacar(-1, 'step', struct('rayleigh', [0.5 0.004])), 'flexmb:spacar:input', 'alpha M');
  flexmb_test_refused(@() spacar(-1, 'step', struct('rayleigh', 0.004)), 'flexmb:spacar:usage', '[alpha beta]');
  flexmb_test_refused(@() spacar(-1, 'step', struct('dampingratio', -1)), 'flexmb:spacar:usage', 'at least 0');
  flexmb_test_refused(@() spacar(-10, 'tf', struct('rayleigh', [0 0.004])), 'flexmb:spacar:usage', 'mode 9 takes');
  flexmb_test_refused(@() spacar(-3, 'tf', struct('rayleigh', [0 0.004])), 'flexmb:spacar:usage', 'static file');
  flexmb_test_refused(@() spacar(-9, 'tf', struct('dampingratio', 0.02, 'reltol', 1e-3)), 'flexmb:spacar:usage', 'mode 9 takes');
end

function write_file(name, text)
  f = fopen(name, 'w');
  fprintf(f, text);
  fclose(f);
end
