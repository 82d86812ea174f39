function test_spacar_refine(src, flexmb)
% spacar(mode, name, opts) with opts.refine (issue 50 item 1): every flexible beam split in N, for
% every mode. The 5-element guidance refined by 2 has more coordinates, its original nodes in their
% places, and a stage motion within the mesh's discretization error of the unrefined one (static
% deflection 12.6547 -> 12.6497 mm: 4e-4); a bad count is a usage error.
  copyfile(fullfile(src, 'datfiles', 'straight_guidance.dat'), 'g.dat');
  o = struct('tend', 0.05);
  a = spacar(-1, 'g', o);
  o.refine = 2;
  b = spacar(-1, 'g', o);
  assert(size(b.x, 2) > size(a.x, 2), 'refined: %d coordinates against %d', size(b.x, 2), size(a.x, 2));
  ca = a.lnp(6, 1); cb = b.lnp(6, 1);
  assert(ca == cb, 'node 6 moved from column %d to %d', ca, cb);
  motion = max(abs(a.x(:, ca) - a.x(1, ca)));
  d = max(abs(b.x(end, cb) - a.x(end, ca)));
  fprintf('stage x after 0.05 s: refine 1 %.9g, refine 2 %.9g (difference %.2e of the motion %.3g)\n', ...
          a.x(end, ca), b.x(end, cb), d / motion, motion);
  assert(d > 0 && d < 5e-3 * motion, 'refine 2 against 1: %.3g of the motion', d / motion);
  spacar(0, 'g', struct('refine', 2));  % a mode without time integration takes it too
  refused(@() spacar(-1, 'g', struct('refine', 0)), 'flexmb:spacar:usage', 'opts.refine');
  refused(@() spacar(-1, 'g', struct('refine', 1.5)), 'flexmb:spacar:usage', 'opts.refine');
end

function refused(run, id, words)
  try
    run();
  catch err
    assert(strcmp(err.identifier, id), '%s (%s)', err.identifier, err.message);
    assert(~isempty(strfind(err.message, words)), err.message);
    return;
  end
  error('accepted: expected %s', words);
end
