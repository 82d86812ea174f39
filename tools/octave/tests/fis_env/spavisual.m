function varargout = spavisual(varargin)
% SPACAR's 3-D viewer is not part of this test: FlexibleInstrumentSimulation's main script calls it
% after every run; here it only checks that the result file it would draw exists.
  name = varargin{1};
  if ~exist([name '.sbd'], 'file')
    error('spavisual:file', 'spavisual: %s.sbd not found', name);
  end
  varargout = cell(1, nargout);
end
