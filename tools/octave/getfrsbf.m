function out = getfrsbf(file, var, step)
% GETFRSBF  A variable from flexmb's SPACAR result files (.sbd, .sbm), as SPACAR's getfrsbf.
%   v = getfrsbf(file, var)        the whole history: per-step quantities (x, xd, xdd, e, ed, edd,
%                                  sig, fxt (also as fxtot), fx, fxgrav, time (also as t)) as tdef x n,
%                                  one row per step; per-step matrices
%                                  (dx, de, bigd, m0, k0, g0, c0, d0, n0, modeq, modex) as tdef x (rows*cols),
%                                  row k the step's matrix flattened column-wise; with one stored step
%                                  the step's value in its natural shape (a column, or the matrix).
%   v = getfrsbf(file, var, step)  the value at one step (1..tdef): a column vector or the matrix.
%   Topology, counts and element constants (lnp, ln, le, it, nx, ne, nxp, nep, ndof, nddof, tdef,
%   rxyz, rl0, x0, estiff, stif, edamp, em) are returned as stored, whatever step. Names are
%   case-insensitive. Layouts: io/results.md. See also checksbf, loadsbd, loadsbm, repinsbf.
%   The .ltv of mode 9 (a, b, c, d, dft, inputnames, outputnames: one step) and of mode 3 (m0, k0b
%   per load step) is read the same way; a matrix stored once (not per step) is returned as it is.
  if nargin < 2 || ~ischar(file) || ~ischar(var)
    error('getfrsbf:usage', 'usage: getfrsbf(file, var[, step])');
  end
  if ~exist(file, 'file')
    error('getfrsbf:file', 'getfrsbf: cannot find ''%s''', file);
  end
  s = load(file, '-mat');
  names = fieldnames(s);
  if strcmpi(var, 'fxtot') && ~any(strcmpi(names, 'fxtot'))
    var = 'fxt';  % SPACAR's workspace name of the total nodal forces; the file holds fxt
  elseif strcmpi(var, 't') && ~any(strcmpi(names, 't'))
    var = 'time';  % SPACAR's name of the time (files of flexmb before issue 52 hold time only)
  end
  k = find(strcmpi(names, var), 1);
  if isempty(k)
    error('getfrsbf:var', 'getfrsbf: %s holds no variable ''%s'' (it holds: %s)', file, var, ...
          strjoin(names', ', '));
  end
  v = s.(names{k});
  if isfield(s, 'tdef')
    tdef = s.tdef;
  else
    tdef = size(v, 1);
  end
  kind = flexmb_sbfkind(var, v, tdef);
  isRows = strcmp(kind, 'rows');
  isPages = strcmp(kind, 'pages');
  if nargin >= 3
    if ~isnumeric(step) || ~isscalar(step) || step ~= fix(step) || step < 1 || step > tdef
      error('getfrsbf:step', 'getfrsbf: step must be an integer from 1 to %d (tdef of %s)', tdef, file);
    end
    if isRows
      out = v(step, :).';
    elseif isPages
      out = v(:, :, step);
    else
      out = v;
    end
    return;
  end
  if isRows
    if tdef == 1
      out = v.';
    else
      out = v;
    end
  elseif isPages
    if tdef == 1
      out = v;
    else
      out = reshape(v, size(v, 1) * size(v, 2), size(v, 3)).';
    end
  else
    out = v;
  end
end
