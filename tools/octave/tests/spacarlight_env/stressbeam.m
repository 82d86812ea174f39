function [a, b, c, extrema] = stressbeam(varargin)
% Stand-in for the beam stress post-processor of SPACAR's Spavisual package (not part of flexmb).
% SPACAR Light reads only extrema.max (MPa) into results.stressmax: NaN here, so a test cannot
% mistake it for a computed stress.
  a = []; b = []; c = [];
  extrema.max = NaN;
  extrema.min = NaN;
end
