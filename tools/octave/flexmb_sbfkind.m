function kind = flexmb_sbfkind(name, v, tdef)
% FLEXMB_SBFKIND  How a variable of a result file (.sbd, .sbm, .ltv) is stored, for getfrsbf,
% checksbf and repinsbf (layouts: io/results.md):
%   'rows'   one row per stored step (tdef x n): time, t, x, xd, xdd, e, ed, edd, sig, fxt, fx,
%            fxgrav, freq
%   'pages'  one matrix per stored step (a x b x tdef): dx, de, bigd, M0, K0, G0, C0, D0, N0, modeq,
%            modex, K0B, and A, B, C, D when they are per step
%   'fixed'  stored once: counts, topology, element constants, and the rest
% name is case-insensitive; v is the stored value and tdef the file's number of steps (a matrix
% of the page list that is not tdef pages deep, such as the .sbm's state-space model, is 'fixed').
  key = lower(name);
  rows = {'time', 't', 'x', 'xd', 'xdd', 'e', 'ed', 'edd', 'sig', 'fxt', 'fx', 'fxgrav', 'freq'};
  pages = {'dx', 'de', 'bigd', 'm0', 'k0', 'g0', 'c0', 'd0', 'n0', 'modeq', 'modex', 'k0b', 'a', 'b', 'c', 'd'};
  if any(strcmp(key, rows))
    kind = 'rows';
  elseif any(strcmp(key, pages)) && (tdef <= 1 || size(v, 3) == tdef)
    kind = 'pages';
  else
    kind = 'fixed';
  end
end
