function varargout = solve(varargin)
% Stand-in for the Symbolic Math Toolbox's solve for a small square system of real equations
% (sym.m expressions, == as lhs - rhs), enough for FlexibleInstrumentSimulation's channel geometry:
% Newton's method from a grid of starts finds the distinct real solutions; with one output per
% variable (variables in alphabetical order, as MATLAB's symvar) each output is a column of
% doubles, one row per solution (MATLAB returns syms; the script applies max and double to them).
% Angles are taken in (-pi, pi] for variables whose name starts with t (the script's t_1_sym):
% the principal solutions MATLAB's solve reports.
  eqs = varargin;
  vars = {};
  for k = 1:numel(eqs), vars = unique([vars, eqs{k}.vars]); end
  n = numel(vars);
  if n ~= numel(eqs), error('solve:square', 'solve stand-in: %d equations in %d unknowns', numel(eqs), n); end
  F = @(z) cellfun(@(e) e.f(cell2struct(num2cell(z(:)), vars(:), 1)), eqs(:));
  angle = cellfun(@(s) s(1) == 't', vars);
  grid1 = linspace(-3, 3, 13);
  [G{1:n}] = ndgrid(grid1);
  sols = zeros(0, n);
  for s = 1:numel(G{1})
    z = cellfun(@(g) g(s), G)';
    for it = 1:60
      r = F(z);
      J = zeros(n);
      for j = 1:n
        dz = zeros(n, 1); dz(j) = 1e-7 * max(1, abs(z(j)));
        J(:, j) = (F(z + dz) - r) / dz(j);
      end
      if rcond(J) < 1e-14, break; end
      step = -J \ r;
      z = z + step;
      if norm(step) < 1e-14 * max(1, norm(z)), break; end
    end
    if all(isfinite(z)) && norm(F(z)) < 1e-10
      z(angle) = mod(z(angle) + pi, 2*pi) - pi;
      z(angle & z == -pi) = pi;
      if isempty(sols) || all(vecnorm(sols - z', 2, 2) > 1e-8)
        sols(end+1, :) = z';
      end
    end
  end
  for k = 1:max(1, nargout)
    varargout{k} = sols(:, k);
  end
end
