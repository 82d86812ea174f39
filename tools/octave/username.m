function u = username()
% SPACAR Light writes the user's name into the .dat header from a variable it sets only on Windows
% (getenv('username')) and macOS (getenv('USER')); on Linux the name resolves to this function, so
% spacarlight.m runs unchanged there (Octave and MATLAB alike). Empty when USER is not set.
  u = getenv('USER');
end
