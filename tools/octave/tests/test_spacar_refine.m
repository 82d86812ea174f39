function test_spacar_refine(src, flexmb)
% spacar(mode, name, opts) with opts.refine (issue 50 item 1): every flexible beam split in N, for
% every mode. The 5-element guidance refined by 2 gives results at the original nodes and elements:
% the unrefined file's layout (lnp, le, the sizes of x and e) and a stage motion within the mesh's
% discretization error of the unrefined one (static deflection 12.6547 -> 12.6497 mm: 4e-4);
% opts.refinedresults gives the refined model's own, more coordinates with the original nodes in
% their places and the same motion; a bad count is a usage error.
  copyfile(fullfile(src, 'datfiles', 'straight_guidance.dat'), 'g.dat');
  o = struct('tend', 0.05);
  a = spacar(-1, 'g', o);
  o.refine = 2;
  b = spacar(-1, 'g', o);
  assert(isequal(size(b.x), size(a.x)) && isequal(size(b.e), size(a.e)), 'refined: x %dx%d, e %dx%d', ...
         size(b.x, 1), size(b.x, 2), size(b.e, 1), size(b.e, 2));
  assert(isequal(b.lnp, a.lnp) && isequal(b.le, a.le), 'the original layout');
  o.refinedresults = true;
  c = spacar(-1, 'g', o);
  assert(size(c.x, 2) > size(a.x, 2), 'refined model: %d coordinates against %d', size(c.x, 2), size(a.x, 2));
  ca = a.lnp(6, 1); cc = c.lnp(6, 1);
  assert(ca == cc, 'node 6 moved from column %d to %d', ca, cc);
  assert(max(abs(b.x(:, ca) - c.x(:, cc))) < 1e-12, 'the values at node 6 are the refined run''s');
  motion = max(abs(a.x(:, ca) - a.x(1, ca)));
  d = max(abs(b.x(end, ca) - a.x(end, ca)));
  fprintf('stage x after 0.05 s: refine 1 %.9g, refine 2 %.9g (difference %.2e of the motion %.3g)\n', ...
          a.x(end, ca), b.x(end, ca), d / motion, motion);
  assert(d > 0 && d < 5e-3 * motion, 'refine 2 against 1: %.3g of the motion', d / motion);
  spacar(0, 'g', struct('refine', 2));  % a mode without time integration takes it too
  flexmb_test_refused(@() spacar(-1, 'g', struct('refine', 0)), 'flexmb:spacar:usage', 'opts.refine');
  flexmb_test_refused(@() spacar(-1, 'g', struct('refine', 1.5)), 'flexmb:spacar:usage', 'opts.refine');
  flexmb_test_refused(@() spacar(-1, 'g', struct('refine', 2, 'refinedresults', 'yes')), 'flexmb:spacar:usage', ...
          'opts.refinedresults');
end
