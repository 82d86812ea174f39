function syms(varargin)
% Stand-in for the Symbolic Math Toolbox's syms (absent in Octave without the symbolic package),
% enough for the one system FlexibleInstrumentSimulation solves: each name becomes a sym (sym.m)
% in the caller's workspace.
  for k = 1:nargin
    assignin('caller', varargin{k}, sym(varargin{k}));
  end
end
