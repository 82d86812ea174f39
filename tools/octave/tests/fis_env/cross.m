function c = cross(a, b, dim)
% The vector cross product with MATLAB's orientation rule: for two 3-element vectors the result is
% a row when either input is a row (Octave 7 returns a column when they differ, with a warning).
% FlexibleInstrumentSimulation's contact function relies on it (cross(omega', ro*nvec') with a
% column and a row, then v_omega*tvec'). Arrays: along dim (default: the first of size 3).
  if nargin == 2 && isvector(a) && isvector(b) && numel(a) == 3 && numel(b) == 3
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)];
    if ~(isrow(a) || isrow(b)), c = c.'; end
    return;
  end
  if nargin < 3, dim = find(size(a) == 3, 1); end
  perm = [dim, setdiff(1:ndims(a), dim)];
  A = permute(a, perm);
  B = permute(b, perm);
  C = [A(2,:).*B(3,:) - A(3,:).*B(2,:); A(3,:).*B(1,:) - A(1,:).*B(3,:); A(1,:).*B(2,:) - A(2,:).*B(1,:)];
  c = ipermute(reshape(C, size(A)), perm);
end
