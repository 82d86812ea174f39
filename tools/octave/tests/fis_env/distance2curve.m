function [xy, distance, t] = distance2curve(curvexy, mapxy, varargin)
% Minimal stand-in for distance2curve (J. D'Errico, MATLAB File Exchange 34869, which
% FlexibleInstrumentSimulation requires and does not ship), 'linear' interpolation only: for each
% point (row) of mapxy the closest point xy on the polyline through the rows of curvexy, its
% distance, and its arc-length fraction t along the polyline. Written for flexmb's tests from the
% definition (orthogonal projection onto each segment, clamped to the segment, nearest kept).
  if nargin > 2 && ~strcmpi(varargin{1}, 'linear')
    error('distance2curve:method', 'this stand-in supports linear interpolation only');
  end
  p0 = curvexy(1:end-1, :);
  d = curvexy(2:end, :) - p0;
  len = sqrt(sum(d.^2, 2));
  cum = [0; cumsum(len)];
  m = size(mapxy, 1);
  xy = zeros(m, size(curvexy, 2));
  distance = zeros(m, 1);
  t = zeros(m, 1);
  dd = sum(d.^2, 2);
  dd(dd == 0) = 1;
  for i = 1:m
    s = sum((mapxy(i, :) - p0) .* d, 2) ./ dd;
    s = min(max(s, 0), 1);
    q = p0 + s .* d;
    dist2 = sum((q - mapxy(i, :)).^2, 2);
    [dmin, k] = min(dist2);
    xy(i, :) = q(k, :);
    distance(i) = sqrt(dmin);
    t(i) = (cum(k) + s(k) * len(k)) / cum(end);
  end
end
