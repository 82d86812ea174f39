function d = datetime(varargin)
% Octave has no datetime class (MATLAB has; this folder is added only where it is missing, by
% PKG_ADD beside spacar.mex). SPACAR Light calls datestr(datetime) for the date line of the .dat
% file it writes; datestr takes the serial date number this returns. Only the current time,
% datetime() or datetime('now'), is supported: other arguments are an error, not a wrong date.
  if nargin > 1 || (nargin == 1 && !(ischar (varargin{1}) && strcmpi (varargin{1}, 'now')))
    error ('flexmb:datetime', ...
           'datetime: Octave has no datetime class; this stand-in gives only the current time (datetime or datetime(''now''))');
  end
  d = now ();
end
