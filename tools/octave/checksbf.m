function out = checksbf(file)
% CHECKSBF  The variables stored in a result file (.sbd, .sbm, .ltv), as SPACAR's checksbf.
%   checksbf(file)      prints, for the file named WITH its extension (as SPACAR's), every variable
%                       with its size, class and whether it is stored per step (one row per step:
%                       time, x, ...; one page per step: dx, M0, ...) or once (counts, topology);
%                       the names are those getfrsbf and repinsbf take.
%   info = checksbf(file)  returns the same as a struct array (name, size, class, kind with kind
%                       'rows', 'pages' or 'fixed') and prints nothing.
% See also getfrsbf, loadsbd, loadsbm, repinsbf.
  if nargin < 1 || ~ischar(file) || isempty(file)
    error('checksbf:usage', 'usage: checksbf(file) with the file name and its extension');
  end
  if ~exist(file, 'file')
    error('checksbf:file', 'checksbf: cannot find ''%s''', file);
  end
  s = load(file, '-mat');
  names = fieldnames(s);
  tdef = 1;
  if isfield(s, 'tdef')
    tdef = s.tdef;
  end
  info = struct('name', names, 'size', [], 'class', [], 'kind', []);
  for k = 1:numel(names)
    v = s.(names{k});
    info(k).size = size(v);
    info(k).class = class(v);
    info(k).kind = flexmb_sbfkind(names{k}, v, tdef);
  end
  if nargout > 0
    out = info;
    return;
  end
  fprintf('%s: %d variables, %d stored steps (tdef)\n', file, numel(names), tdef);
  what = struct('rows', 'per step (row k = step k)', 'pages', 'per step (page k = step k)', 'fixed', '');
  for k = 1:numel(info)
    dims = sprintf('%d x ', info(k).size);
    fprintf('  %-12s %-16s %-7s %s\n', info(k).name, dims(1:end - 3), info(k).class, what.(info(k).kind));
  end
end
