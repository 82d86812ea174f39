function test_study_loop(src, flexmb)
% The design-study loop of tools/octave/README.md ("Design studies from a script") runs as written,
% and gives the first frequency in the last equilibrium that `flexmb study` gives for the same leaf
% thicknesses (the shipped template computes the section from t with the formulas of write_pivot).
  t = [0.15e-3, 0.2e-3, 0.35e-3, 0];   % t = 0: a variant that fails (no stiffness, no mass)
  f1 = nan(size(t));
  for i = 1:numel(t)
    name = sprintf('pivot_%02d', i);
    write_pivot([name '.dat'], src, t(i));
    try
      r = spacar(-10, name);
      f1(i) = r.freq(end, 1);
    catch err
      fprintf('%s: %s\n', name, err.message);
    end
  end
  assert(all(isfinite(f1(1:3))) && isnan(f1(4)), 'the loop: f1 = %s', mat2str(f1));
  cmd = sprintf('"%s" study "%s" --param t=%s --static -q --out cli', flexmb, ...
                fullfile(src, 'datfiles', 'spatial', 'cross_spring_pivot_study.dat'), ...
                strjoin(arrayfun(@(v) sprintf('%.17g', v), t(1:3), 'UniformOutput', false), ','));
  [status, out] = system(cmd);
  assert(status == 0, 'flexmb study: %s', out);
  fid = fopen(fullfile('cli', 'study_summary.csv'));
  header = strsplit(fgetl(fid), ',');
  rows = textscan(fid, repmat('%s', 1, numel(header)), 'Delimiter', ',');
  fclose(fid);
  col = find(strcmp(header, 'static_f1_Hz'));
  assert(~isempty(col), 'no static_f1_Hz column in %s', strjoin(header, ','));
  cli = str2double(rows{col})';
  rel = abs(f1(1:3) ./ cli - 1);
  assert(all(rel < 1e-8), 'Octave loop %s against flexmb study %s', mat2str(f1(1:3), 12), mat2str(cli, 12));
  fprintf('Octave loop and flexmb study agree: f1 = %s Hz (largest difference %.1e)\n', mat2str(cli, 8), max(rel));
end

function write_pivot(file, src, t)
% The coarse cross-spring pivot with the leaves' ESTIFF and EM for a leaf thickness t (w = 50 mm,
% E = 210 GPa, G = 70 GPa, rho = 7800 kg/m^3), as datfiles/spatial/cross_spring_pivot_study.dat.
  w = 0.05; E = 210e9; G = 70e9; rho = 7800;
  A = w * t; Iy = w * t^3 / 12; Iz = t * w^3 / 12;
  It = w * t^3 * (1/3 - 0.21 * (t / w) * (1 - (t / w)^4 / 12));
  k = 10 * (E / (2 * G)) / (12 + 11 * (E / (2 * G) - 1));
  estiff = sprintf(' %.17g', E * A, G * It, E * Iy, E * Iz, E * Iy / (k * G * A), E * Iz / (k * G * A));
  em = sprintf(' %.17g', rho * A, rho * (Iy + Iz), rho * Iy, rho * Iz, 0);
  txt = fileread(fullfile(src, 'datfiles', 'spatial', 'cross_spring_pivot_coarse.dat'));
  txt = regexprep(txt, '^(ESTIFF\s+\d+)[^\n]*', ['$1' estiff], 'lineanchors');
  txt = regexprep(txt, '^(EM\s+\d+)[^\n]*', ['$1' em], 'lineanchors');
  fid = fopen(file, 'w');
  fputs(fid, txt);
  fclose(fid);
end
