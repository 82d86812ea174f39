function test_spacarlight(src, flexmb)
% Issue 21 item 7 (issue 12's last item before it): SPACAR Light (github.com/precision-utwente/spalight,
% commit in tools/octave/fetch_public_scripts.sh) runs unchanged with only flexmb's build/octave on
% the path: its own example spacarexample.m as published (a cross-spring pivot of two warping leaf
% springs, BEAMW, under gravity, a moment -0.025 -> 0.025 N m and 1 N on the body) and the same
% script with each of its commented options switched on (calcbuck, transfer = {true 0.01} with
% transfer_in/out on the body, calccompl = false) and with the options spacarlight.m accepts
% besides (mode = 3, rigidstress, stressperelement). SPACAR Light is not part of flexmb: without a
% copy (tools/octave/fetch_public_scripts.sh, or FLEXMB_SPALIGHT_DIR) the test is skipped (exit 77).
% Nothing is added for Octave: flexmb's folder ships username.m (SPACAR Light sets it only on
% Windows and macOS) and, through its PKG_ADD, datetime where Octave lacks it. Checks use theory and
% statics, not flexmb's own output: equilibrium of every load step (the nodal forces of all nodes
% sum to zero; the clamps carry the weight), the rotation M / (2 EI / L) and compliance L / (2 EI)
% of the pivot, the state-space static gain against SPACAR Light's compliance, the leaves' bending
% stress 3 M / (w t^2), the same equilibria in modes 10 and 3.
  here = fileparts(mfilename('fullpath'));
  dir = getenv('FLEXMB_SPALIGHT_DIR');
  if isempty(dir)
    dir = fullfile(src, 'tools', 'octave', 'public', 'spalight');
  end
  if ~exist(fullfile(dir, 'spacarlight.m'), 'file')
    printf('SKIPPED: SPACAR Light''s spacarlight.m not found in %s: run tools/octave/fetch_public_scripts.sh (needs network) or set FLEXMB_SPALIGHT_DIR\n', dir);
    exit(77);
  end
  [status, commit] = system(sprintf('git -C "%s" rev-parse HEAD 2>/dev/null', dir));
  if status ~= 0, commit = '(not a git checkout)'; end
  printf('spacarlight.m from %s, commit %s\n', dir, strtrim(commit));
  addpath(dir);
  % Issue 34 item 7: what SPACAR Light needs beyond spacar comes from flexmb's folder alone.
  for f = {'username', 'datetime'}
    w = which(f{1});
    assert(isempty(strfind(w, 'tests')), '%s comes from the tests, not from flexmb''s folder: %s', f{1}, w);
  end
  if ~exist('OCTAVE_VERSION', 'builtin') || isempty(strfind(which('datetime'), 'compat'))
    % MATLAB, or an Octave with its own datetime: nothing of flexmb's in the way.
  else
    assert(~isempty(datestr(datetime)), 'datestr(datetime) gave nothing');
  end
  warning('off', 'all');
  for f = {'spacar', 'getfrsbf', 'getss', 'stressbeam', 'spavisual'}
    assert(~isempty(strfind(which(f{1}), 'octave')), '%s is not flexmb''s (%s)', f{1}, which(f{1}));
  end
  % BEAMW (eprops.warping = true) needs flexmb's warping beam; without it the published runs are
  % made without warping and the test reports itself skipped at the end.
  write('probe.dat', sprintf(['BEAMW 1 1 2 3 4 5 6 0 0 1\nX 4 1 0 0\nFIX 1\nFIX 2\nFIX 3\nDYNE 1 1 2 3 4 5 6\n' ...
                              'END\nHALT\nESTIFF 1 1 1 1 1 0 0 1\nEND\nEND\n']));
  [status, text] = system(sprintf('"%s" check probe.dat', flexmb));
  warping = status == 0;
  if ~warping
    printf('NOTE: flexmb has no BEAMW yet (%s): the example runs without warping\n', strtrim(text));
  end
  script = fileread(fullfile(dir, 'spacarexample.m'));
  if ~warping
    script = strrep(script, 'eprops(1).warping  = true;', 'eprops(1).warping  = false;');
    script = strrep(script, 'eprops(2).warping  = true;', 'eprops(2).warping  = false;');
  end
  g = 9.81;
  w = 50e-3; t = 0.2e-3; E = 210e9; L = norm([0.1 0.1]);
  EI = E * w * t^3 / 12;
  mleaf = 7800 * w * t * L;
  mtotal = 0.1 + 3000 * 50e-3 * 10e-3 * 0.1 + 2 * mleaf;

  % 1. As published.
  tic;
  out = runScript('ex_published', script);
  elapsed = toc;
  tdef = getfrsbf('crosshinge.sbd', 'tdef');
  assert(tdef == 10 && numel(out.step) == tdef, 'published: %d steps, tdef %d (load steps 0..9)', numel(out.step), tdef);
  balance('crosshinge', out, g * mtotal, g * mleaf / 3, 'published');
  assert(all(isfinite(out.stressmax)) && all(out.stressmax > 0), 'published: stressmax %s', mat2str(out.stressmax));
  assert(isstruct(out.fighandle), 'published: spavisual''s handle');
  printf('published example: %d load steps, body rotation %.5f rad at the end, f1 %.3f Hz, max stress %.1f MPa, %.2f s end to end\n', ...
         tdef, axang_z(out.step(end).node(3).r_axang), out.step(end).freq(1), max(out.stressmax) / 1e6, elapsed);

  % 2. calcbuck: load multipliers in every step, eig(-K0, G0) as SPACAR Light computes them.
  outb = runScript('ex_calcbuck', uncomment(script, 'opt.calcbuck'));
  for i = 1:numel(outb.step)
    b = outb.step(i).buck;
    assert(numel(b) == getfrsbf('crosshinge.sbd', 'nddof') && all(~isnan(b)) && all(b > 0), 'calcbuck step %d', i);
  end
  assert(max(abs(outb.step(end).node(3).p - out.step(end).node(3).p)) < 1e-12, 'calcbuck changed the equilibrium');
  printf('calcbuck: lowest load multiplier %.4g at the last step\n', outb.step(end).buck(1));

  % 3. calccompl = false: no compliance matrices, the same equilibria.
  outc = runScript('ex_nocompl', uncomment(script, 'opt.calccompl'));
  assert(~isfield(outc.step(end).node(3), 'CMglob') || isempty(outc.step(end).node(3).CMglob), 'calccompl = false');
  assert(max(abs(outc.step(end).node(3).p - out.step(end).node(3).p)) < 1e-12, 'calccompl changed the equilibrium');

  % 4. mode = 3: the same load steps with the matrices of each (file crosshinge_3).
  out3 = runScript('ex_mode3', strrep(script, '%% CALL SPACAR_LIGHT', sprintf('opt.mode = 3;\n%%%% CALL SPACAR_LIGHT')));
  assert(numel(out3.step) == tdef, 'mode 3: %d steps', numel(out3.step));
  for i = 1:tdef
    assert(max(abs(out3.step(i).node(3).p - out.step(i).node(3).p)) < 1e-12 && ...
           max(abs(out3.step(i).freq - out.step(i).freq)) < 1e-9 * max(out.step(i).freq), 'mode 3 step %d', i);
  end
  assert(getfrsbf('crosshinge_3.sbd', 'mode') == 3 && exist('crosshinge_3.ltv', 'file') == 2, 'mode 3 files');

  % 5. rigidstress and stressperelement: the rigid body's stress joins the maximum; per element the
  %    largest of the flexible ones is the maximum without rigidstress.
  opts = sprintf('opt.rigidstress = true;\nopt.stressperelement = true;\n%%%% CALL SPACAR_LIGHT');
  outs = runScript('ex_stress', strrep(script, '%% CALL SPACAR_LIGHT', opts));
  for i = 1:tdef
    el = [outs.step(i).element.stressmax];
    assert(numel(el) == 3 && abs(max(el([1 3])) - out.step(i).stressmax) <= 1e-9 * out.step(i).stressmax, ...
           'stressperelement step %d: %s against %g', i, mat2str(el), out.step(i).stressmax);
    assert(abs(outs.step(i).stressmax - max(el)) <= 1e-9 * max(el), 'rigidstress step %d', i);
  end

  % 6. transfer = {true 0.01} with transfer_in / transfer_out on the body (SPACAR Light forbids loads
  %    with it, so the example's force and moments are left out): gravity only, mode 9, getss.
  st = uncomment(script, 'opt.transfer');
  for line = {'nprops(3).force ', 'nprops(3).moment_initial', 'nprops(3).moment '}
    st = regexprep(st, ['\n' regexptranslate('escape', line{1}) '[^\n]*'], '');
  end
  st = strrep(st, '%% CALL SPACAR_LIGHT', sprintf(['nprops(3).transfer_in = {''force_y''};\n' ...
               'nprops(3).transfer_out = {''displ_y'', ''veloc_y''};\n%%%% CALL SPACAR_LIGHT']));
  outt = runScript('ex_transfer', st);
  ss = outt.statespace;
  assert(isstruct(ss) || isobject(ss), 'transfer: no state-space model');
  assert(strcmp(ss.InputName{1}, 'force-y n3') && strcmp(ss.OutputName{2}, 'veloc-y n3'), 'transfer: channel names');
  n = size(ss.a, 1);
  gain = -ss.c * (ss.a \ ss.b) + ss.d;
  C = outt.step(end).node(3).CMglob(2, 2);
  assert(abs(gain(1) - C) < 1e-6 * abs(C), 'transfer: static gain %.10g against the compliance %.10g', gain(1), C);
  assert(abs(gain(2)) < 1e-9 * abs(C), 'transfer: the velocity has no static gain');
  p = eig(ss.a);  % modal damping 0.01 in every mode: -zeta w +- i w sqrt(1 - zeta^2)
  wn = abs(p);
  assert(max(abs(-real(p) ./ wn - 0.01)) < 1e-6, 'transfer: modal damping ratios %s', mat2str(-real(p) ./ wn, 4));
  fnum = sort(unique(round(wn / (2 * pi) * 1e6) / 1e6));
  % eig of the nonsymmetric A finds a pole p to about eps ||A|| / |p| only (the BEAMW warping masses
  % make ||A|| ~ 1e11 against |p1| ~ 9), and fnum is rounded to 1e-6 Hz.
  tolPole = max(1e-6, 100 * eps * norm(ss.a, 1) / (2 * pi * fnum(1)));
  assert(abs(fnum(1) - outt.step(end).freq(1)) < tolPole * fnum(1), 'transfer: poles %.9g Hz against the frequency %.9g Hz (tolerance %.2g)', ...
         fnum(1), outt.step(end).freq(1), tolPole);
  printf('transfer: %d states, static gain %.6g m/N = compliance %.6g m/N, lowest pole %.4f Hz\n', n, gain(1), C, fnum(1));

  % 7. The pivot under a small moment (no gravity, no force): rotation M / (2 EI / L) and compliance
  %    L / (2 EI) (each leaf, crossing at its middle, gives EI / L about the crossing point), and the
  %    leaves' bending stress (M / 2) (t / 2) / I = 3 M / (w t^2).
  M = 0.005;
  sm = regexprep(script, '\nnprops\(3\)\.(force|moment_initial|mass)[^\n]*', '');
  sm = regexprep(sm, '\nnprops\(3\)\.moment\s*=[^;]*;', sprintf('\nnprops(3).moment = [0 0 %g];', M));
  sm = regexprep(sm, '\nopt\.gravity[^\n]*', '');
  sm = regexprep(sm, '\nopt\.filename[^\n]*', sprintf('\nopt.filename = ''pivot_moment'';'));
  outm = runScript('ex_moment', sm);
  K = 2 * EI / L;
  theta = axang_z(outm.step(end).node(3).r_axang);
  assert(abs(theta - M / K) < 1e-2 * M / K, 'moment: rotation %.6g rad, 2EI/L gives %.6g', theta, M / K);
  Cz = outm.step(1).node(3).CMglob(6, 6);
  assert(abs(Cz - 1 / K) < 1e-2 / K, 'moment: compliance %.6g rad/(N m), L/(2EI) gives %.6g', Cz, 1 / K);
  sig = 3 * M / (w * t^2);
  assert(abs(outm.stressmax(end) / sig - 1) < 0.05, 'moment: max stress %.4g Pa, 3M/(w t^2) gives %.4g', ...
         outm.stressmax(end), sig);
  printf('moment: rotation %.6g rad (2EI/L: %.6g), compliance %.6g (L/(2EI): %.6g), stress %.4g MPa (3M/(wt^2): %.4g)\n', ...
         theta, M / K, Cz, 1 / K, outm.stressmax(end) / 1e6, sig / 1e6);
  if ~warping
    printf('SKIPPED: every check passed, but without BEAMW the published example ran without warping\n');
    exit(77);
  end
  printf('PASSED: spacarexample.m as published and with each option, only flexmb on the path\n');
end

% Runs a variant of the example script in its own workspace (the script starts with clear).
function out = runScript(name, text)
  write([name '.m'], text);
  run(fullfile(pwd, [name '.m']));
end

function s = uncomment(script, option)
  s = regexprep(script, ['\n% (' regexptranslate('escape', option) ')'], '\n$1');
  assert(~strcmp(s, script), 'option %s not found commented out in spacarexample.m', option);
end

% Equilibrium of every load step: the total nodal forces fxt of all position nodes sum to zero, and
% the clamps (SPACAR Light's nodes 1, 4) carry the weight less the gravity that acts on the clamp
% nodes themselves (fxgrav there: the clamped beam elements' consistent share, half of each clamped
% element's weight for a straight leaf, 2 x m_leaf/6 of the 3-beam leaves; the bent leaf moves it a
% little, so that share is checked against the straight-leaf value only to 1e-4).
function balance(name, out, weight, clampShare, what)
  fxt = getfrsbf([name '.sbd'], 'fxt');
  fxgrav = getfrsbf([name '.sbd'], 'fxgrav');
  lnp = getfrsbf([name '.sbd'], 'lnp');
  pos = find(all(lnp(:, 1:3) > 0, 2) & (size(lnp, 2) < 4 | lnp(:, min(4, end)) == 0));
  for i = 1:numel(out.step)
    F = zeros(1, 3);
    for j = pos'
      F = F + fxt(i, lnp(j, 1:3));
    end
    assert(norm(F) < 1e-9, '%s step %d: the nodal forces do not balance (sum %s)', what, i, mat2str(F));
    atClamps = -(fxgrav(i, lnp(1, 3)) + fxgrav(i, lnp(10, 3)));  % user nodes 1, 4: position nodes 1, 10
    assert(abs(atClamps - clampShare) < 1e-4 * clampShare, '%s step %d: gravity on the clamp nodes %.10g N, straight leaves %.10g N', ...
           what, i, atClamps, clampShare);
    weightAtClamps = weight - atClamps;
    Fz = out.step(i).node(1).Freac(3) + out.step(i).node(4).Freac(3);
    assert(abs(Fz - weightAtClamps) < 1e-9 * weightAtClamps, '%s step %d: the clamps carry %.10g N, the weight %.10g N', ...
           what, i, Fz, weightAtClamps);
  end
end

function write(name, text)
  f = fopen(name, 'w');
  fprintf(f, '%s', text);
  fclose(f);
end

function a = axang_z(r)
  a = r(1) * r(4);   % angle times the z component of the axis
end
