function test_spacar_helpers(src, flexmb)
% Issue 21 items 3-6 in real Octave with only build/octave on the path: spacar(9) and getss (the
% state-space model of a mass-spring-damper, exact; the struct SPACAR Light modifies), spacar(3) on
% a static file (.ltv with M0 and K0B over the kinematic degrees of freedom, load steps 0..nsteps),
% stressbeam against hand formulas (N/A, M c/I, St Venant torsion of a thin strip and a square,
% a round bar under everything, a BEAMW bimoment), spavisual headless (returns at once, a struct
% whose Children.XLabel.String can be set).
  here = pwd;
  % --- mode 9 and getss -------------------------------------------------------------------------
  m = 4; k = 400; d = 2;
  write('ms.dat', sprintf(['PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2 2\nDYNE 1 1\nEND\nHALT\n' ...
                           'ESTIFF 1 %g\nEDAMP 1 %g\nXM 2 %g\nITERSTEP 10 1\nEND\nHALT\n' ...
                           'INPUTF 1 2 1\nOUTX 1 2 1\nOUTXP 2 2 1\nEND\nEND\n'], k, d, m));
  r = spacar(-9, 'ms');
  assert(r.mode == 9 && r.tdef == 2, 'mode 9: mode %d, tdef %d (load steps 0 and 1)', r.mode, r.tdef);
  assert(exist('ms.ltv', 'file') == 2, 'mode 9 wrote no ms.ltv');
  sys = getss('ms');
  assert(isstruct(sys) && all(isfield(sys, {'a', 'b', 'c', 'd', 'InputName', 'OutputName'})), 'getss: struct fields');
  assert(norm(sys.a - [0 1; -k / m -d / m]) < 1e-12 * k, 'getss: A = %s', mat2str(sys.a));
  assert(norm(sys.b - [0; 1 / m]) < 1e-15 && norm(sys.c - eye(2)) < 1e-12 && norm(sys.d) == 0, 'getss: B, C, D');
  assert(numel(sys.InputName) == 1 && numel(sys.OutputName) == 2 && ischar(sys.OutputName{2}), 'getss: names');
  [A, B, C, D] = getss('ms.ltv', 1);
  assert(isequal(A, sys.a) && isequal(B, sys.b) && isequal(C, sys.c) && isequal(D, sys.d), 'getss: four outputs');
  assert(getfrsbf('ms.ltv', 'DFT') == 0, 'DFT of a model without feedthrough');
  % With the control package (octave-control, which tools/setup.sh installs) loaded: an ss object of
  % the same matrices and channel names; unloaded again, the struct SPACAR Light's uses need.
  if ~isempty(pkg('list', 'control'))
    pkg load control
    obj = getss('ms');
    assert(isa(obj, 'ss'), 'getss with the control package: a %s, not an ss object', class(obj));
    [a2, b2, c2, d2] = ssdata(obj);
    assert(isequal(a2, A) && isequal(b2, B) && isequal(c2, C) && isequal(d2, D), 'getss: the ss object''s matrices');
    assert(isequal(obj.inname(:), sys.InputName(:)) && isequal(obj.outname(:), sys.OutputName(:)), ...
           'getss: the ss object''s channel names');
    poles = sort(pole(obj));
    assert(norm(poles - sort(eig(A))) < 1e-9 * norm(poles), 'getss: the ss object''s poles');
    pkg unload control
    assert(isstruct(getss('ms')), 'getss after pkg unload control: not the struct');
    fprintf('getss with the control package: an ss object, poles %s\n', mat2str(poles.', 6));
  else
    fprintf('NOTE: octave-control is not installed (tools/setup.sh installs it): getss''s ss object not tested\n');
  end
  % What SPACAR Light does with it: modal damping from M0 and the mass-normalised modes, names.
  M0 = getfrsbf('ms.sbm', 'm0', r.tdef);
  K0 = getfrsbf('ms.sbm', 'k0', r.tdef);
  [V, L] = eig(K0, M0);
  L = diag(L);
  V = V * diag(1 ./ sqrt(diag(V.' * M0 * V)));
  n = size(sys.a, 1);
  sys.a(n / 2 + 1:n, n / 2 + 1:n) = -V * 2 * 0.01 * diag(sqrt(L)) * V' * M0;
  sys.InputName{1} = 'force-x n2';
  sys.OutputName{1} = 'displ-x n2';
  assert(abs(sys.a(2, 2) + 2 * 0.01 * sqrt(k / m)) < 1e-12, 'modal damping in the state order of M0');
  fprintf('mode 9: A = %s, getss struct modified as SPACAR Light does\n', mat2str(sys.a, 6));

  % --- mode 3 on a static file --------------------------------------------------------------------
  write('base.dat', ['PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nINPUTX 1 1\nFIX 1 2\nFIX 2 2\nDYNE 1 1\nEND\nHALT\n' ...
                     'ESTIFF 1 300\nEM 1 0.6\nXM 2 2\nDELINPX 1 1 0.1\nITERSTEP 10 4\nEND\nEND\n']);
  r = spacar(-3, 'base');
  assert(r.mode == 3 && r.tdef == 5, 'mode 3: mode %d, tdef %d (load steps 0..4)', r.mode, r.tdef);
  x = getfrsbf('base.sbd', 'x');
  lnp = getfrsbf('base.sbd', 'lnp');
  assert(norm(x(:, lnp(1, 1)) - (0:4)' * 0.025) < 1e-12, 'mode 3: the input moves 0.1 in 4 steps');
  for s = 1:r.tdef
    M = getfrsbf('base.ltv', 'M0', s);
    KB = getfrsbf('base.ltv', 'K0B', s);
    assert(isequal(size(M), [r.ndof r.ndof]) && r.ndof == 2, 'mode 3: M0 over ndof');
    Mexp = [0.2 + 0.2 + 2.2, 0.1 + 2.2; 0.1 + 2.2, 2.2];
    assert(norm(M - Mexp) < 1e-12 && abs(KB(2, 2) - getfrsbf('base.sbm', 'k0', s)) < 1e-9 && norm(KB(:, 1)) < 1e-9, ...
           'mode 3 step %d: M0 %s, K0B %s', s, mat2str(M), mat2str(KB));
  end
  fprintf('mode 3 on a static file: %d load steps, .ltv M0/K0B %s\n', r.tdef, mat2str(size(KB)));

  % --- stressbeam ---------------------------------------------------------------------------------
  w = 0.05; t = 0.002; l0 = 0.1;
  A = w * t; Iy = w * t^3 / 12; Iz = t * w^3 / 12;
  rect = struct('CrossSection', 'rect', 'Dimensions', [w t]);
  opt = struct('exterior', true);
  % One BEAM (element 1) with sig = [N, T/l0, My_p/l0, My_q/l0, Mz_p/l0, Mz_q/l0] per step.
  N = 100; T = 0.02; My = 0.3; Mz = 2;
  sig = [N 0 0 0 0 0; 0 0 My / l0 0 0 0; 0 0 0 0 Mz / l0 0; 0 T / l0 0 0 0 0; N 0 0 -My / l0 0 0];
  fake('beam.sbd', sig, 1:6, l0, []);
  [s1, ~, ~, ex] = stressbeam('beam.sbd', 1, [], opt, rect);
  It = w * t^3 / 3 * (1 - 192 / pi^5 * (t / w) * sum(tanh((1:2:2001) * pi * w / (2 * t)) ./ (1:2:2001).^5));  % the series to 1e-15
  expect = [N / A, My * (t / 2) / Iy, Mz * (w / 2) / Iz, sqrt(3) * T * t / It, N / A + My * (t / 2) / Iy] / 1e6;
  assert(max(abs(s1 - expect) ./ expect) < 1e-9, 'stressbeam: %s, hand formulas %s', mat2str(s1, 8), mat2str(expect, 8));
  % The thin-strip formula with its first correction, It = w t^3/3 (1 - 0.630 t/w): tau = T t/It.
  assert(abs(s1(4) / (sqrt(3) * 3 * T / (w * t^2 * (1 - 0.630 * t / w)) / 1e6) - 1) < 1e-3, 'thin-strip torsion');
  assert(abs(ex.max - max(expect)) < 1e-9 * max(expect) && ex.step == 5 && ex.element == 1, 'stressextrema');
  % A square section under torsion: tau_max = T / (0.2082 a^3) (St Venant).
  a = 0.01;
  fake('square.sbd', [0 T / l0 0 0 0 0], 1:6, l0, []);
  s2 = stressbeam('square.sbd', 1, 1, opt, struct('CrossSection', 'rect', 'Dimensions', [a a]));
  assert(abs(s2 * 1e6 / (sqrt(3) * T / (0.2082 * a^3)) - 1) < 1e-3, 'square torsion: %g', s2);
  % A round bar under N, both bending moments and torsion: sqrt((N/A + M r/I)^2 + 3 (T r/Ip)^2).
  dd = 0.01; r0 = dd / 2; Ac = pi * dd^2 / 4; Ic = pi * dd^4 / 64;
  fake('round.sbd', [N T / l0 My / l0 0 Mz / l0 0], 1:6, l0, []);
  s3 = stressbeam('round.sbd', 1, 1, opt, struct('CrossSection', 'circ', 'Dimensions', dd));
  e3 = sqrt((N / Ac + hypot(My, Mz) * r0 / Ic)^2 + 3 * (T * r0 / (2 * Ic))^2) / 1e6;
  assert(abs(s3 / e3 - 1) < 1e-12, 'round bar: %g, expected %g', s3, e3);
  % BEAMW: torque l0 (sig2 - sig7 - sig8) and the bimoment E Cw (4 e7 + 2 e8) / l0^3 at p.
  ECw = 210e9 * w^3 * t^3 / 144; e7 = 1e-6; Cw = w^3 * t^3 / 144;
  fake('beamw.sbd', [0 0 0 0 0 0 0 0], [1:6 7 8], l0, [0 0 0 0 0 0 ECw], [0 0 0 0 0 0 e7 0]);
  s4 = stressbeam('beamw.sbd', 1, 1, opt, rect);
  e4 = ECw * 4 * e7 / l0^3 * (w / 2) * (t / 2) / Cw / 1e6;
  assert(abs(s4 / e4 - 1) < 1e-12, 'BEAMW bimoment: %g, expected %g', s4, e4);
  fprintf('stressbeam: N/A, M c/I, torsion (strip, square), round bar, bimoment as the hand formulas\n');

  % --- spavisual ----------------------------------------------------------------------------------
  copyfile(fullfile(src, 'datfiles', 'cantilever.dat'), 'cant.dat');
  tic;
  results.fighandle = spavisual('cant');
  assert(toc < 30, 'spavisual took %g s', toc);
  results.fighandle.Children.XLabel.String = 'x';
  results.fighandle.Children.YLabel.String = 'y';
  assert(strcmp(results.fighandle.file, 'cant_model.svg') && exist(fullfile(here, 'cant_model.svg'), 'file') == 2, ...
         'spavisual: no picture (%s)', results.fighandle.message);
  h = spavisual('no_such_model');
  assert(isempty(h.file) && ~isempty(h.message), 'spavisual without a model: a note, no error');
  fprintf('spavisual: %s, headless\n', results.fighandle.file);
  fprintf('PASSED: spacar(9), getss, spacar(3) on a static file, stressbeam, spavisual\n');
end

function write(name, text)
  f = fopen(name, 'w');
  fprintf(f, text);
  fclose(f);
end

% A .sbd holding one element with the given generalised stresses per step (rows), deformation places
% defs, reference length l0, stif row and deformations e (zeros when empty).
function fake(name, sig, defs, l0, stifrow, e)
  if nargin < 6
    e = zeros(size(sig));
  end
  tdef = size(sig, 1);
  le = defs;
  rl0 = l0;
  stif = stifrow;
  it = 1;
  if isempty(stif)
    stif = zeros(1, 6);
  end
  save('-mat', name, 'sig', 'le', 'rl0', 'tdef', 'e', 'stif', 'it');
end
