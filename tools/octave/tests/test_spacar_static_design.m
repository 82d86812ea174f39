function test_spacar_static_design(src, flexmb)
% Issue 53 item 1 through spacar(10, ...): the .sbd holds SPACAR Light's stressmax and Freac / Mreac
% beside SPACAR's variables, and stressbeam (tools/octave) on the same .sbd gives the same stress.
% The model is datfiles/cantilever.dat with a 20 x 2 mm section: P L (t/2)/I = 7.5 MPa at the clamp
% under the tip load P = 0.1 N (the arm shortened by the deflection: 7.4994 MPa), reaction 0.1 N.
  text = fileread(fullfile(src, 'datfiles', 'cantilever.dat'));
  fid = fopen('design.dat', 'w');
  fprintf(fid, '%s', text);
  fprintf(fid, 'VISUALIZATION\nBEAMPROPS 1 2 3 4\nCROSSTYPE RECT\nCROSSDIM 0.02 0.002\n');
  fclose(fid);
  spacar(10, 'design');
  d = load('design.sbd', '-mat');
  I = 0.02 * 0.002^3 / 12;
  assert(abs(d.stressmax(end) / (0.1 * 0.001 / I) - 1) < 1e-4, 'stressmax %g', d.stressmax(end));
  assert(isequal(size(d.stressel), [4, 2]), 'stressel is %s', mat2str(size(d.stressel)));
  assert(abs(d.Freac(2, end, 1) - 0.1) < 1e-12, 'Freac %g', d.Freac(2, end, 1));
  for i = 1:4
    pc(i).CrossSection = 'rect';
    pc(i).Dimensions = [0.02 0.002];
  end
  s = stressbeam('design.sbd', 1:4, [], struct('exterior', true), pc);
  assert(max(abs(s(:, end) * 1e6 - d.stressel(:, end))) < 1e-6 * d.stressmax(end), 'stressbeam differs');
  printf('stressmax %.6g Pa, Freac %.6g N: as beam theory and stressbeam\n', d.stressmax(end), d.Freac(2, end, 1));
end
