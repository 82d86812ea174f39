function h = spavisual(varargin)
% SPACAR's 3-D viewer (not part of flexmb). SPACAR Light only checks that it exists when it is
% called with opt.spavisual = false or opt.silent = true.
  error('spavisual:missing', 'spavisual (SPACAR''s viewer) is not part of flexmb');
end
