function out = loadsbd(name)
% LOADSBD  Every variable of a result file name.sbd into the caller's workspace, as SPACAR's loadsbd.
%   loadsbd(name)      creates or overwrites, in the workspace of the caller, one variable per
%                      variable of name.sbd (name without the extension, as SPACAR's; 'name.sbd' is
%                      taken too), with the layouts of the file (io/results.md), as spacar() puts
%                      them there after a run: counts (nx, ne, ndof, nddof, nxp, nep, tdef), topology
%                      (lnp, le, ln, it, rxyz, ...), the steps (time, x, xd, xdd, e, ed, edd, sig, fx,
%                      fxgrav, fxt and its SPACAR name fxtot, dx, de, bigd where the run stored them)
%                      and mode (which spacar() leaves out: it hides Octave's mode()).
%   s = loadsbd(name)  returns them in a struct instead and leaves the workspace alone.
% The file's t (SPACAR's name of the time) is time. SPACAR's loadsbd also lists nkdof, nkddof,
% xcompl, dxc, dec, d2x and d2e: flexmb does not write them (their meaning is not public; the docs
% page for Octave says what is known), so they are not created.
% See also getfrsbf, loadsbm, checksbf, repinsbf, spacar.
  if nargin < 1 || ~ischar(name) || isempty(name)
    error('loadsbd:usage', 'usage: loadsbd(name) with name the result file without .sbd');
  end
  if numel(name) > 4 && strcmpi(name(end - 3:end), '.sbd')
    name = name(1:end - 4);
  end
  file = [name '.sbd'];
  if ~exist(file, 'file')
    error('loadsbd:file', 'loadsbd: cannot find ''%s''', file);
  end
  s = load(file, '-mat');
  if isfield(s, 't')
    s = rmfield(s, 't');
  end
  if isfield(s, 'fxt') && ~isfield(s, 'fxtot')
    s.fxtot = s.fxt;  % SPACAR's workspace name of the total nodal forces
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
