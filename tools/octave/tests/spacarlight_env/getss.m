function sys = getss(varargin)
% SPACAR's state-space builder (mode 9, not part of flexmb). SPACAR Light calls it only with
% opt.transfer; it checks that it exists in every run.
  error('getss:missing', 'getss (SPACAR''s state-space builder, mode 9) is not part of flexmb');
end
