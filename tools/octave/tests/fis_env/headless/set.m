function set(varargin)
% Stand-in for a machine without a graphics toolkit (test_fis.m adds this folder only then):
% graphics properties are ignored.
end
