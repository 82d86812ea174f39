function d = datetime(varargin)
% Octave 7 has no datetime class; SPACAR Light only passes datetime() to datestr for a comment
% line of the .dat file, and datestr takes a datenum.
  d = now();
end
