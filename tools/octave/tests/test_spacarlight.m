function test_spacarlight(src, flexmb)
% Issue 12, last acceptance item: a public script that drives SPACAR through spacar() and
% getfrsbf() runs unchanged with flexmb. The script is SPACAR Light's spacarlight.m
% (github.com/precision-utwente/spalight, commit in tools/octave/fetch_public_scripts.sh); it is
% not part of flexmb: tools/octave/fetch_public_scripts.sh clones it into tools/octave/public/, or
% FLEXMB_SPALIGHT_DIR names a folder holding spacarlight.m. Without it the test is skipped (exit
% code 77, ctest's SKIP_RETURN_CODE). spacarlight_env/ holds stand-ins for what the script needs
% beyond spacar and getfrsbf (tools/octave/README.md). Checks use theory and statics, not flexmb's
% own output: the cross-spring pivot's rotational stiffness 2 EI / L, its compliance from complt
% (dx, K0, G0, N0), and the balance of the reaction forces read from fxt.
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
  addpath(fullfile(here, 'spacarlight_env'));
  warning('off', 'all');

  % SPACAR Light's own example (spacarexample.m: cross-spring pivot, moment -0.025 -> 0.025 N m and
  % 1 N along y on the body, 3 beams per leaf), without warping (flexmb has no BEAMW) and without
  % gravity (flexmb's statics does not converge with it: tools/octave/README.md).
  [nodes, elements, nprops, eprops] = pivot();
  nprops(3).force = [0 1 0];
  nprops(3).moment_initial = [0 0 -0.025];
  nprops(3).moment = [0 0 0.05];
  nprops(3).mass = 0.1;
  opt.filename = 'crosshinge';
  opt.spavisual = false;
  out = spacarlight(nodes, elements, nprops, eprops, opt);
  tdef = getfrsbf('crosshinge.sbd', 'tdef');
  assert(numel(out.step) == tdef && tdef > 1, 'example: %d result steps for tdef %d', numel(out.step), tdef);
  for i = 1:tdef
    F = zeros(1, 3);
    for j = 1:4
      F = F + out.step(i).node(j).Freac;
    end
    % Reactions at the clamps (nodes 1, 4) balance the applied load on node 3 (fxt = applied + support).
    assert(norm(F) < 1e-9, 'example step %d: the nodal forces do not balance (sum %s)', i, mat2str(F));
    assert(isreal(out.step(i).freq) && all(out.step(i).freq > 0), 'example step %d: frequencies', i);
    assert(isequal(out.step(i).node(1).p, [0 0 0]), 'example step %d: clamped node 1 moved', i);
  end
  assert(norm(out.step(end).node(3).Freac - [0 1 0]) < 1e-12, 'example: applied force on node 3');
  printf('example: %d load steps, rotation of the body %.5f rad at the end, first frequency %.2f Hz\n', ...
         tdef, axang_z(out.step(end).node(3).r_axang), out.step(end).freq(1));

  % The same pivot under a small moment only: rotation M / (2 EI / L) (each leaf, crossing at its
  % middle, gives EI / L about the crossing point) and compliance L / (2 EI) about z.
  [nodes, elements, nprops, eprops] = pivot();
  M = 0.005;
  nprops(3).moment = [0 0 M];
  opt = struct('filename', 'pivot_moment', 'spavisual', false);
  out = spacarlight(nodes, elements, nprops, eprops, opt);
  L = norm(nodes(3, :) - nodes(1, :));
  w = eprops(1).dim(1); t = eprops(1).dim(2);
  EI = eprops(1).emod * w * t^3 / 12;
  K = 2 * EI / L;
  theta = axang_z(out.step(end).node(3).r_axang);
  assert(abs(theta - M / K) < 1e-2 * M / K, 'moment: rotation %.6g rad, 2EI/L gives %.6g', theta, M / K);
  C = out.step(1).node(3).CMglob(6, 6);
  assert(abs(C - 1 / K) < 1e-2 / K, 'moment: compliance %.6g rad/(N m), L/(2EI) gives %.6g', C, 1 / K);
  printf('moment: rotation %.6g rad (2EI/L: %.6g), compliance %.6g (L/(2EI): %.6g)\n', theta, M / K, C, 1 / K);
  printf('PASSED: spacarlight.m ran unchanged with flexmb''s spacar and getfrsbf\n');
end

function [nodes, elements, nprops, eprops] = pivot()
  nodes = [0 0 0; 0 0.1 0; 0.1 0.1 0; 0.1 0 0];
  elements = [1 3; 2 3; 2 4];
  nprops(1).fix = true;
  nprops(4).fix = true;
  eprops(1).elems = [1 3];
  eprops(1).emod = 210e9;
  eprops(1).smod = 70e9;
  eprops(1).dens = 7800;
  eprops(1).cshape = 'rect';
  eprops(1).dim = [50e-3 0.2e-3];
  eprops(1).orien = [0 0 1];
  eprops(1).nbeams = 3;
  eprops(1).flex = 1:6;
  eprops(2).elems = 2;
  eprops(2).dens = 3000;
  eprops(2).cshape = 'rect';
  eprops(2).dim = [50e-3 10e-3];
  eprops(2).orien = [0 0 1];
  eprops(2).nbeams = 1;
end

function a = axang_z(r)
  a = r(1) * r(4);   % angle times the z component of the axis
end
