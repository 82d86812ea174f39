function repinsbf(file, id, value, step)
% REPINSBF  Replaces the value of a variable in a result file (.sbd, .sbm, .ltv), as SPACAR's repinsbf.
%   repinsbf(file, id, value)        a variable stored once (counts, topology, element constants):
%                                    value must have exactly the stored size.
%   repinsbf(file, id, value, step)  a variable stored per step (checksbf says which): its value at
%                                    step 1..tdef, of the size getfrsbf(file, id, step) returns (a
%                                    vector may be a row or a column).
% file is named WITH its extension (as SPACAR's); id as checksbf shows it (case-insensitive; fxtot
% is fxt, and time and t, the same time, change together). THE FILE IS MODIFIED: it is written again
% (MAT v7, compressed) under a temporary name and then moved over the old one. The step is ignored
% for a variable stored once, as SPACAR's help says.
% See also getfrsbf, checksbf, loadsbd, loadsbm.
  if nargin < 3 || ~ischar(file) || ~ischar(id)
    error('repinsbf:usage', 'usage: repinsbf(file, id, value[, step])');
  end
  if ~exist(file, 'file')
    error('repinsbf:file', 'repinsbf: cannot find ''%s''', file);
  end
  if ~isnumeric(value) && ~islogical(value) || ~isreal(value)
    error('repinsbf:value', 'repinsbf: the value must be real numbers');
  end
  s = load(file, '-mat');
  names = fieldnames(s);
  if strcmpi(id, 'fxtot') && ~any(strcmpi(names, 'fxtot'))
    id = 'fxt';
  end
  k = find(strcmpi(names, id), 1);
  if isempty(k)
    error('repinsbf:var', 'repinsbf: %s holds no variable ''%s'' (it holds: %s)', file, id, strjoin(names', ', '));
  end
  n = names{k};
  v = s.(n);
  tdef = 1;
  if isfield(s, 'tdef')
    tdef = s.tdef;
  end
  kind = flexmb_sbfkind(n, v, tdef);
  value = double(value);
  if strcmp(kind, 'fixed')
    if ~isequal(size(value), size(v))
      error('repinsbf:size', 'repinsbf: %s is %s, the value %s', n, sizeText(size(v)), sizeText(size(value)));
    end
    v = value;
  else
    if nargin < 4 || ~isnumeric(step) || ~isscalar(step) || step ~= fix(step) || step < 1 || step > tdef
      error('repinsbf:step', 'repinsbf: %s is stored per step: give the step, an integer from 1 to %d', n, tdef);
    end
    if strcmp(kind, 'rows')
      if ~isvector(value) || numel(value) ~= size(v, 2)
        error('repinsbf:size', 'repinsbf: %s at a step is %d x 1, the value %s', n, size(v, 2), sizeText(size(value)));
      end
      v(step, :) = value(:).';
    else
      if ~isequal(size(value), [size(v, 1) size(v, 2)])
        error('repinsbf:size', 'repinsbf: %s at a step is %s, the value %s', n, sizeText([size(v, 1) size(v, 2)]), ...
              sizeText(size(value)));
      end
      v(:, :, step) = value;
    end
  end
  s.(n) = v;
  for same = {'time', 't'}  % the two names of the time change together
    if any(strcmpi(n, {'time', 't'})) && isfield(s, same{1})
      s.(same{1}) = v;
    end
  end
  tmp = [file '.repinsbf.tmp'];
  save(tmp, '-struct', 's', '-v7');  % MATLAB's argument order (Octave takes it too)
  [ok, msg] = movefile(tmp, file, 'f');
  if ~ok
    delete(tmp);
    error('repinsbf:write', 'repinsbf: cannot replace %s: %s', file, msg);
  end
end

function t = sizeText(sz)
  t = sprintf('%d x ', sz);
  t = t(1:end - 3);
end
