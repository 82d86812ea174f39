function b = flexmb_test_bytes(path)
% The bytes of a file, for the tests that compare spacar()'s files with the command line's.
  f = fopen(path, 'rb');
  assert(f >= 0, 'cannot open %s', path);
  b = fread(f, Inf, 'uint8=>uint8');
  fclose(f);
end
