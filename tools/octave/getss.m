function varargout = getss(filename, ts)
% GETSS  The state-space model a mode-9 run stored (name.ltv), as SPACAR's getss.
%   sys = getss(name)            the model of name.ltv (the name without or with .ltv);
%   sys = getss(name, ts)        the model of stored step ts (mode 9 stores one: the last load step);
%   [A, B, C, D] = getss(...)    the four matrices.
%   d/dt [dq; dqd] = A [dq; dqd] + B u,  y = C [dq; dqd] + D u,  the states in the order of the
%   degrees of freedom (the rows of M0 in name.sbm), A = [0 I; -M0\(K0+N0+G0) -M0\(C0+D0)].
%   With one output: an ss object when ss() is available (Octave: pkg load control; MATLAB: the
%   Control System Toolbox), otherwise a struct with the fields a, b, c, d (D is zeros when the
%   file's DFT is 0), InputName and OutputName (cell columns of the channel names), which
%   SPACAR Light's uses accept (sys.a(i, j) = ..., sys.InputName{j} = ...).
  if nargin < 1 || nargin > 2 || ~ischar(filename)
    error('getss:usage', 'usage: sys = getss(name[, ts]) or [A, B, C, D] = getss(name[, ts])');
  end
  if nargout == 2 || nargout == 3
    error('getss:usage', 'getss returns one state-space model or the four matrices A, B, C, D');
  end
  if nargin < 2
    ts = 1;
  end
  if numel(filename) <= 4 || ~strcmpi(filename(end-3:end), '.ltv')
    filename = [filename '.ltv'];
  end
  if ~exist(filename, 'file')
    error('getss:file', 'getss: cannot find ''%s'' (run spacar(9, name) on a file with a transfer block first)', ...
          filename);
  end
  A = getfrsbf(filename, 'A', ts);
  B = getfrsbf(filename, 'B', ts);
  C = getfrsbf(filename, 'C', ts);
  if getfrsbf(filename, 'DFT')
    D = getfrsbf(filename, 'D', ts);
  else
    D = zeros(size(C, 1), size(B, 2));
  end
  if nargout >= 2
    varargout = {A, B, C, D};
    return;
  end
  s = load(filename, '-mat');
  inNames = names(s, 'inputnames', size(B, 2), 'u');
  outNames = names(s, 'outputnames', size(C, 1), 'y');
  if exist('ss') == 2 || exist('ss') == 6 || exist('ss') == 8
    sys = ss(A, B, C, D);
    try
      sys = set(sys, 'InputName', inNames, 'OutputName', outNames);
    catch  % an ss without named channels is still the model
    end
  else
    sys = struct('a', A, 'b', B, 'c', C, 'd', D);
    sys.InputName = inNames;
    sys.OutputName = outNames;
  end
  varargout = {sys};
end

function c = names(s, field, n, letter)
  c = cell(n, 1);
  for k = 1:n
    c{k} = sprintf('%s%d', letter, k);
  end
  if isfield(s, field) && ischar(s.(field)) && size(s.(field), 1) == n
    for k = 1:n
      c{k} = strtrim(s.(field)(k, :));
    end
  end
end
