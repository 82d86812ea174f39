function out = loadsbm(name)
% LOADSBM  Every variable of a result file name.sbm into the caller's workspace, as SPACAR's loadsbm.
%   loadsbm(name)      creates or overwrites, in the workspace of the caller, one variable per
%                      variable of name.sbm (name without the extension, as SPACAR's; 'name.sbm' is
%                      taken too): ndof, nddof, tdef, time and the linearised matrices under SPACAR's
%                      lower-case names m0, k0, g0, c0, d0, n0 (nddof x nddof x tdef), with freq,
%                      modeq, modex and the state-space A, B, C, D, DFT where the run stored them.
%   s = loadsbm(name)  returns them in a struct instead and leaves the workspace alone.
% flexmb's k0 is the structural stiffness K0 alone and n0 the dynamic stiffening N0 (SPACAR's help
% of 2001 says that its k0 held K0 + N0 in that release). SPACAR's loadsbm also lists nkdof,
% nkddof, nnom, ak0, bk0 and b0: flexmb does not write them (their meaning is not public), so they
% are not created.
% See also getfrsbf, loadsbd, checksbf, repinsbf, spacar.
  if nargin < 1 || ~ischar(name) || isempty(name)
    error('loadsbm:usage', 'usage: loadsbm(name) with name the result file without .sbm');
  end
  if numel(name) > 4 && strcmpi(name(end - 3:end), '.sbm')
    name = name(1:end - 4);
  end
  file = [name '.sbm'];
  if ~exist(file, 'file')
    error('loadsbm:file', 'loadsbm: cannot find ''%s''', file);
  end
  f = load(file, '-mat');
  names = fieldnames(f);
  lower6 = {'m0', 'k0', 'g0', 'c0', 'd0', 'n0'};
  s = struct();
  for k = 1:numel(names)
    n = names{k};
    if strcmp(n, 't')
      continue;  % SPACAR's name of the time: it is time
    elseif any(strcmpi(n, lower6))
      s.(lower(n)) = f.(n);
    else
      s.(n) = f.(n);
    end
  end
  if nargout > 0
    out = s;
    return;
  end
  names = fieldnames(s);
  for k = 1:numel(names)
    assignin('caller', names{k}, s.(names{k}));
  end
end
