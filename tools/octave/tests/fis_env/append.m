function s = append(varargin)
% Stand-in for MATLAB's append (R2019a), absent in Octave 7: concatenates character vectors keeping
% their trailing blanks (strcat would drop them: FlexibleInstrumentSimulation builds
% append('TIMESTEP ', num2str(tlim), ' 8000 ...')). Cell arguments are joined element-wise.
  if any(cellfun(@iscell, varargin))
    n = max(cellfun(@(a) iscell(a) * numel(a), varargin));
    s = cell(1, n);
    for k = 1:n
      parts = cellfun(@(a) pick(a, k), varargin, 'UniformOutput', false);
      s{k} = [parts{:}];
    end
  else
    s = [varargin{:}];
  end
end

function p = pick(a, k)
  if iscell(a), p = a{k}; else, p = a; end
end
