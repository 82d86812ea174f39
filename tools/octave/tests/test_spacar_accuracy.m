function test_spacar_accuracy(src, flexmb)
% spacar(mode, name, opts) with opts.accuracy and opts.errorestimate (issue 50 item 3), as the command
% line's --accuracy and --error-estimate: mode 10 on the cantilever under a large tip load against
% Mattiasson's elastica (P L^2 / EI = 2: tip at u / L = 0.16064, w / L = 0.49346), the results at the
% original nodes; mode 1 on the guidance says its total error estimate; bad values are usage errors.
  text = fileread(fullfile(src, 'datfiles', 'cantilever.dat'));
  text = strrep(text, 'DELXF 5  0.0  -0.1', 'DELXF 5  0.0  -5.6');
  text = strrep(text, 'ITERSTEP 10 1', 'ITERSTEP 30 10');
  fid = fopen('elastica.dat', 'w'); fprintf(fid, '%s', text); fclose(fid);
  a = spacar(-10, 'elastica');
  b = spacar(-10, 'elastica', struct('accuracy', 1e-3));
  assert(isequal(size(b.x), size(a.x)), 'the original layout: x %dx%d against %dx%d', size(b.x), size(a.x));
  tip = a.lnp(5, 1:2);
  err = @(r) max(abs([1 - r.x(end, tip(1)) - 0.16064, -r.x(end, tip(2)) - 0.49346])) / 0.49;
  fprintf('elastica tip off Mattiasson: 4 PLBEAM %.2e, opts.accuracy 1e-3 %.2e of the motion\n', err(a), err(b));
  assert(err(a) > 5e-3 && err(b) <= 1e-3, 'elastica: %.3g and %.3g', err(a), err(b));
  copyfile(fullfile(src, 'datfiles', 'straight_guidance.dat'), 'g.dat');
  out = evalc('spacar(1, ''g'', struct(''tend'', 0.05, ''errorestimate'', true));');
  assert(~isempty(strfind(out, 'total error estimate:')), out);
  assert(~isempty(strfind(out, 'at refine 1 (Richardson from refine 1, 2, 4')), out);
  flexmb_test_refused(@() spacar(-1, 'g', struct('accuracy', 2)), 'flexmb:spacar:usage', 'opts.accuracy');
  flexmb_test_refused(@() spacar(-1, 'g', struct('accuracy', 1e-2, 'errorestimate', true)), 'flexmb:spacar:usage', 'not both');
  flexmb_test_refused(@() spacar(-9, 'g', struct('accuracy', 1e-2)), 'flexmb:spacar:usage', 'modes 1, 3, 4 and 10');
end
