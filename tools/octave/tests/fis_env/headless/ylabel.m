function varargout = ylabel(varargin)
% Stand-in for a machine without a graphics toolkit (test_fis.m adds this folder only then):
% FlexibleInstrumentSimulation's plotting lines run and draw nothing.
  varargout = cell(1, nargout);
end
