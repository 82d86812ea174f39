function test_spacar_paper(src, flexmb)
% spacar(1, model) on the paper's models gives, bit for bit, the variables `flexmb simulate` writes,
% in the caller's workspace and in the returned struct; x(:, lnp(n, k)) is coordinate k of node n
% (the CLI's CSV column node<n>.<k-th>); e(:, le(el, j)) deformation j of element el.
  models = {'straight_guidance', 'manipulator', 'slider_crank_s95'};
  for m = 1:numel(models)
    name = models{m};
    copyfile(fullfile(src, 'datfiles', [name '.dat']), '.');
    mkdir('cli');
    [status, out] = system(sprintf('"%s" simulate %s.dat --format both --out cli/%s -q', flexmb, name, name));
    assert(status == 0, 'flexmb simulate %s failed: %s', name, out);
    t0 = tic;
    r = spacar(-1, name);   % silent; variables into this workspace, struct returned
    fprintf('%s: spacar(1) in %.2f s\n', name, toc(t0));
    assert(isequal(flexmb_test_bytes(fullfile('cli', [name '.sbd'])), flexmb_test_bytes([name '.sbd'])), ...
           '%s: %s.sbd is not the bytes flexmb simulate writes', name, name);
    cli = load(fullfile('cli', [name '.sbd']), '-mat');
    names = fieldnames(cli);
    for k = 1:numel(names)
      v = names{k};
      if strcmp(v, 't')  % SPACAR's file name of the time: spacar() gives it as time (SPACAR's loadsbd does)
        assert(~isfield(r, 't') && isequal(cli.t, cli.time), '%s: t', name);
        continue;
      end
      assert(isfield(r, v), '%s: struct lacks %s', name, v);
      assert(isequal(r.(v), cli.(v)), '%s: %s differs from flexmb simulate', name, v);
      if ~strcmp(v, 'mode')   % kept out of the workspace (it would hide Octave's mode())
        assert(isequal(eval(v), cli.(v)), '%s: workspace %s differs from flexmb simulate', name, v);
      end
    end
    % x(:, lnp(n, k)) against the CSV table of the command line (model order, named columns).
    [hx, X] = readTable(fullfile('cli', [name '_x.csv']));
    [he, E] = readTable(fullfile('cli', [name '_e.csv']));
    assert(isequal(X(:, 1), time), '%s: time', name);
    nodes = zeros(0, 2);
    for c = 2:numel(hx)
      tok = regexp(hx{c}, '^node(\d+)\.', 'tokens', 'once');
      n = str2double(tok{1});
      k = sum(nodes(:, 1) == n) + 1;
      nodes(end + 1, :) = [n k];
      assert(isequal(x(:, lnp(n, k)), X(:, c)), '%s: x(:, lnp(%d, %d)) is not %s', name, n, k, hx{c});
    end
    for c = 2:numel(he)
      tok = regexp(he{c}, '^[A-Za-z]+(\d+)\.e(\d+)_', 'tokens', 'once');
      el = str2double(tok{1}); j = str2double(tok{2});
      assert(isequal(e(:, le(el, j)), E(:, c)), '%s: e(:, le(%d, %d)) is not %s', name, el, j, he{c});
    end
    fprintf('%s: %d variables bit-identical to flexmb simulate; %d coordinates and %d deformations checked via lnp/le\n', ...
            name, numel(names), size(nodes, 1), numel(he) - 1);
    clear -x src flexmb models m
  end
end

function [h, A] = readTable(path)
  fid = fopen(path, 'r');
  h = strsplit(fgetl(fid), ',');
  fclose(fid);
  A = dlmread(path, ',', 1, 0);
end
