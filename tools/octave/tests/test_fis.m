function test_fis(src, flexmb)
% Issue 23's acceptance: FlexibleInstrumentSimulation's main script (a brachytherapy source cable
% pushed through an S-shaped channel; USERSIG FFESFVA for contact and friction, USERINP FFESMVA for
% the pushed motion, flexible BEAM model) runs through flexmb's spacar() with its own user functions
% and its own post-processing and plotting lines. FIS is not part of flexmb:
% tools/octave/fetch_public_scripts.sh clones it into tools/octave/public/, or FLEXMB_FIS_DIR names a
% copy; without one the test is skipped (exit code 77). The script's text is used unchanged except
% for the simulation velocity vel_sim (FLEXMB_FIS_VEL, default 12 m/s instead of 0.1), which
% shortens the simulated span 0.12 / vel_sim to 0.01 s: the insertion is continuous only when the
% depth stays 0.12 (FFESMVA jumps to 0 after its time limit). fis_env/ holds Octave stand-ins for
% MATLAB functions Octave 7 lacks (tools/octave/README.md); fis_env/headless/ stands in for the
% plotting commands where Octave has no graphics toolkit; its spavisual call is flexmb's own
% (build/octave/spavisual.m). Checks are independent of flexmb's code:
% the input follows FFESMVA's law, the cable keeps its segment lengths (elongations are rigid), and
% fx at the tip equals what FIS's own FFESFVA returns at the stored states.
  here = fileparts(mfilename('fullpath'));
  dir = getenv('FLEXMB_FIS_DIR');
  if isempty(dir)
    dir = fullfile(src, 'tools', 'octave', 'public', 'FlexibleInstrumentSimulation');
  end
  main = 'm20221212_RS_WP2_MAT_CatheterInsertionForce_V5';
  fns = fullfile(dir, 'Functions');
  if ~exist(fullfile(fns, [main '.m']), 'file')
    printf('SKIPPED: FlexibleInstrumentSimulation not found in %s: run tools/octave/fetch_public_scripts.sh (needs network) or set FLEXMB_FIS_DIR\n', dir);
    exit(77);
  end
  vel = str2double(getenv('FLEXMB_FIS_VEL'));
  if isnan(vel), vel = 12; end
  copyfile(fullfile(fns, '*'), '.');
  text = fileread([main '.m']);
  short = regexprep(text, 'vel_sim\s*=\s*0\.1;', sprintf('vel_sim  = %g;', vel), 'once');
  assert(~strcmp(short, text), 'vel_sim = 0.1 not found in %s.m', main);
  fid = fopen('fis_main_short.m', 'w');
  fprintf(fid, '%s', short);
  fclose(fid);
  addpath(fullfile(here, 'fis_env'));
  if isempty(available_graphics_toolkits())
    addpath(fullfile(here, 'fis_env', 'headless'));
  end
  t0 = tic;
  evalin('base', 'fis_main_short');  % the script clears the workspace it runs in: the base one
  total = toc(t0);
  sim = evalin('base', 'sim');
  assert(exist('FLEX_CAT_S_3D_V3.sbd', 'file') == 2, 'the run''s FLEX_CAT_S_3D_V3.sbd is missing');
  time = evalin('base', 'time'); x = evalin('base', 'x'); xd = evalin('base', 'xd');
  fx = evalin('base', 'fx'); lnp = evalin('base', 'lnp');
  s = sim.flex;
  tend = 0.12 / vel;
  tlim = 0.12 / (2 * vel);
  printf('FIS main script, vel_sim = %g m/s (%g s simulated): %.1f s in all, spacar %.1f s\n', vel, tend, total, s.t_sim);
  % The output grid of the script's TIMESTEP (8000 intervals) and its post-processing shapes.
  assert(numel(time) == 8001 && abs(time(end) - tend) < 1e-12, '%d output times to %g', numel(time), time(end));
  assert(isequal(size(s.x), [8001 25 3]) && isequal(size(s.f_fil), [8001 1]), 'post-processing shapes');
  % FFESMVA's law at the input (node 49 along x): -0.12 + 2 vel t up to tlim, 0 after.
  law = (time <= tlim) .* (-0.12 + 2 * vel * time);
  assert(max(abs(s.x_in(:, 1) - law)) < 1e-9, 'input position: %g', max(abs(s.x_in(:, 1) - law)));
  % Rigid elongations: every segment keeps its 5 mm.
  seg = sqrt(sum(diff(s.x, 1, 2) .^ 2, 3));
  assert(max(abs(seg(:) - 0.005)) < 1e-6, 'segment lengths: %g', max(abs(seg(:) - 0.005)));
  % fx at the tip is FFESFVA's force at the stored state (every 400th output time).
  worst = 0; scale = max(1e-3, max(abs(s.f_1(:))));
  for k = 1:400:numel(time)
    [~, ~, f] = FFESFVA(time(k), 0, [], [], [], size(x, 2), lnp, x(k, :), xd(k, :));
    tip = f(f(:, 1) == 1, :);
    F = zeros(1, 3);
    F(tip(:, 2)) = tip(:, 3);
    worst = max(worst, max(abs(fx(k, lnp(1, 1:3)) - F)));
  end
  assert(worst <= 1e-9 * scale, 'fx at the tip differs from FFESFVA by %g (scale %g)', worst, scale);
  % The script's plot: insertion force over insertion depth.
  if evalin('base', 'exist(''flexmb_plots'', ''var'')')
    plots = evalin('base', 'flexmb_plots');
    assert(isequal(plots{1}{1}, s.x_in(:, 1) + 0.12) && isequal(plots{1}{2}, s.f_fil), 'the plotted curve');
  end
  printf('tip force up to %.3g N, input force (fxtot) from %.3g to %.3g N, filtered at the end %.3g N\n', ...
         max(sqrt(sum(s.f_1 .^ 2, 2))), min(s.f_in(:, 1)), max(s.f_in(:, 1)), s.f_fil(end));
end
