function tf = matches(str, pattern, varargin)
% Stand-in for MATLAB's matches (R2019b), absent in Octave 7: true where str equals pattern (or one
% of the patterns of a cell), optionally ignoring case. FlexibleInstrumentSimulation's main script
% chooses its model with matches('rig', sim_mod).
  ignoreCase = numel(varargin) >= 2 && strcmpi(varargin{1}, 'IgnoreCase') && logical(varargin{2});
  if ~iscell(pattern), pattern = {pattern}; end
  if iscell(str)
    tf = cellfun(@(s) matches(s, pattern, varargin{:}), str);
    return;
  end
  if ignoreCase
    tf = any(strcmpi(str, pattern));
  else
    tf = any(strcmp(str, pattern));
  end
end
