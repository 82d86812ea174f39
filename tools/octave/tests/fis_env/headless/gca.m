function h = gca()
% Stand-in for a machine without a graphics toolkit (test_fis.m adds this folder only then).
  h = -1;
end
