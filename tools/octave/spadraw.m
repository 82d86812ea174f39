function h = spadraw(name, step)
% SPADRAW  The mechanism of a result file name.sbd in a MATLAB/Octave figure, as SPACAR's spadraw.
%   spadraw(name)        draws the elements of name.sbd (name without the extension, as SPACAR's;
%                        'name.sbd' is taken too) at its first stored step, with a slider over the
%                        stored steps (the output times) when there are several (not with Octave's
%                        gnuplot toolkit, which draws no uicontrol); the figure is named
%                        'Spacar: name [k/tdef] t = ...'.
%   spadraw(name, k)     at stored step k (1..tdef).
%   spadraw()            asks for the file (uigetfile), as SPACAR's.
%   h = spadraw(...)     (only when asked for) a struct: figure, axes, lines (one line per drawn element), slider, step,
%                        ndim (2 or 3), elements (labels), codes (it), p and q (node labels), color
%                        (one RGB row per element), time, and X, Y, Z (elements x 2 x tdef: the
%                        coordinates of p and q at every stored step; Z is [] in a planar model).
% As SPACAR's, only beams and trusses are drawn, one line from node p to node q each, chosen by
% SPACAR's element codes `it` (io/results.md): planar 5 PLBEAM (blue, q = ln(:, 3)), 7 PLTRUSS
% (green, q = ln(:, 2)), 10 PLPINBODY (red), 15 PLTUBE (orange); spatial 1 BEAM (blue, q = ln(:, 3)),
% 2 TRUSS (green, q = ln(:, 2)), 9 PINBODY (red), 16 TUBE (orange), 17 SCREW (purple), 18 BEAMW
% (light blue, q = ln(:, 4)); p is ln(:, 1). flexmb adds its RBEAM (code 103, grey, q = ln(:, 3)),
% which SPACAR's spadraw does not know; hinges (3) and Euler-parameter normalisations (4) are not
% drawn. Axes: equal scales (not for a spatial model with Octave's gnuplot toolkit, which cannot
% show them), limits over every stored step; a spatial model is seen from azimuth 130, elevation 40.
% Without graphics (octave-cli without a display or gnuplot, or a figure that cannot be made) it
% draws nothing, says why, and returns h with figure [] and the coordinates all the same; flexmb's
% SVG picture of a model is spavisual(name).
% See also spavisual, getfrsbf, loadsbd.
  if nargin < 1
    [f, p] = uigetfile('*.sbd', 'Open a result file (.sbd)');
    if isequal(f, 0)
      h = [];
      return;
    end
    name = fullfile(p, f);
  end
  if ~ischar(name) || isempty(name)
    error('spadraw:usage', 'usage: spadraw(name[, step]) with name the result file without .sbd');
  end
  if numel(name) > 4 && strcmpi(name(end - 3:end), '.sbd')
    name = name(1:end - 4);
  end
  h = spadrawData(name);
  h.name = name;
  if nargin < 2
    step = 1;
  end
  tdef = numel(h.time);
  if ~isnumeric(step) || ~isscalar(step) || step ~= fix(step) || step < 1 || step > tdef
    error('spadraw:step', 'spadraw: the step must be an integer from 1 to %d (tdef of %s.sbd)', tdef, name);
  end
  h.step = step;
  h.figure = [];
  h.axes = [];
  h.lines = [];
  h.slider = [];
  why = spadrawNoGraphics();
  if isempty(why)
    try
      h = spadrawFigure(h, name);
    catch err
      delete(findobj(0, 'Type', 'figure', 'Tag', 'SpaDraw'));  % what was made of it
      h.figure = [];
      h.axes = [];
      h.lines = [];
      h.slider = [];
      why = err.message;
    end
  end
  if ~isempty(why)
    fprintf('spadraw: %s.sbd not drawn (%s); the coordinates are in the returned struct, spavisual(''%s'') writes an SVG picture\n', ...
            name, why, name);
  end
  if nargout == 0
    clear h;  % spadraw(name) without a semicolon (oopspa's test_slidercrank.m) prints no struct
  end
end

% The elements to draw and their coordinates at every stored step.
function d = spadrawData(name)
  file = [name '.sbd'];
  if ~exist(file, 'file')
    error('spadraw:file', 'spadraw: cannot find ''%s''', file);
  end
  s = load(file, '-mat');
  for need = {'lnp', 'ln', 'it', 'x', 'time'}
    if ~isfield(s, need{1})
      error('spadraw:file', 'spadraw: %s holds no ''%s''', file, need{1});
    end
  end
  % code, column of ln that is node q, colour
  drawn = {5, 3, [0 0 1]; 7, 2, [0 0.5 0]; 10, 3, [1 0 0]; 15, 3, [1 0.5 0]; ...
           1, 3, [0 0 1]; 2, 2, [0 0.5 0]; 9, 3, [1 0 0]; 16, 3, [1 0.5 0]; 17, 3, [0.5 0 0.5]; ...
           18, 4, [0.5 0.5 1]; 103, 3, [0.5 0.5 0.5]};
  spatialCodes = [1 2 3 9 16 17 18];
  lnp = s.lnp;
  ln = s.ln;
  it = s.it(:);
  d.ndim = 2;
  if size(lnp, 2) >= 3 || any(ismember(it, spatialCodes))
    d.ndim = 3;
  end
  d.time = s.time(:);
  d.elements = zeros(0, 1);
  d.codes = zeros(0, 1);
  d.p = zeros(0, 1);
  d.q = zeros(0, 1);
  d.color = zeros(0, 3);
  for el = 1:numel(it)
    row = find([drawn{:, 1}] == it(el), 1);
    if isempty(row) || size(ln, 2) < drawn{row, 2}
      continue;
    end
    p = ln(el, 1);
    q = ln(el, drawn{row, 2});
    if p < 1 || q < 1
      continue;
    end
    d.elements(end + 1, 1) = el;
    d.codes(end + 1, 1) = it(el);
    d.p(end + 1, 1) = p;
    d.q(end + 1, 1) = q;
    d.color(end + 1, :) = drawn{row, 3};
  end
  x = s.x;
  if size(x, 1) ~= numel(d.time)
    x = x.';  % one stored step may come as a column
  end
  n = numel(d.elements);
  tdef = numel(d.time);
  d.X = zeros(n, 2, tdef);
  d.Y = zeros(n, 2, tdef);
  d.Z = [];
  if d.ndim == 3
    d.Z = zeros(n, 2, tdef);
  end
  for k = 1:n
    ends = [d.p(k) d.q(k)];
    d.X(k, :, :) = reshape(x(:, lnp(ends, 1)).', 1, 2, tdef);
    d.Y(k, :, :) = reshape(x(:, lnp(ends, 2)).', 1, 2, tdef);
    if d.ndim == 3
      d.Z(k, :, :) = reshape(x(:, lnp(ends, 3)).', 1, 2, tdef);
    end
  end
end

% Why no figure can be made here ('' when one can).
function why = spadrawNoGraphics()
  why = '';
  if exist('available_graphics_toolkits') && isempty(available_graphics_toolkits())
    why = 'no graphics toolkit in this Octave';
  end
end

% The figure (SPACAR's, tagged 'SpaDraw', reused when one is open): a line per element at step
% h.step, limits over all steps, a slider over the steps when there are several.
function h = spadrawFigure(h, name)
  tdef = numel(h.time);
  f = findobj(0, 'Type', 'figure', 'Tag', 'SpaDraw');
  if isempty(f)
    f = figure('Tag', 'SpaDraw', 'NumberTitle', 'off', 'Color', [1 1 1]);
  else
    f = f(1);
    clf(f);
  end
  h.figure = f;
  h.axes = axes('Parent', f, 'XGrid', 'on', 'YGrid', 'on', 'ZGrid', 'on', 'Position', [0.2 0.08 0.78 0.9]);
  if h.ndim == 2 || spadrawHasControls(f)  % equal scales (gnuplot shrinks a 3-D plot with them to a dot)
    set(h.axes, 'DataAspectRatio', [1 1 1]);
  end
  n = numel(h.elements);
  h.lines = zeros(n, 1);
  if exist('gobjects')  % MATLAB: graphics objects, not numbers
    h.lines = gobjects(n, 1);
  end
  for k = 1:n
    args = {'Parent', h.axes, 'XData', h.X(k, :, h.step), 'YData', h.Y(k, :, h.step), 'Color', h.color(k, :), ...
            'LineWidth', 2};
    if h.ndim == 3
      args = [args, {'ZData', h.Z(k, :, h.step)}];
    end
    h.lines(k) = line(args{:});
  end
  % Limits over every stored step, padded by 5 % of the largest extent (so that a model flat in one
  % direction, such as a planar mechanism drawn in 3-D, keeps a visible depth).
  coords = {h.X, h.Y, h.Z};
  lo = zeros(1, h.ndim);
  hi = zeros(1, h.ndim);
  for a = 1:h.ndim
    if ~isempty(coords{a})
      lo(a) = min(coords{a}(:));
      hi(a) = max(coords{a}(:));
    end
  end
  pad = max(0.05 * max(hi - lo), 1e-14);
  names = {'XLim', 'YLim', 'ZLim'};
  for a = 1:h.ndim
    set(h.axes, names{a}, [lo(a) - pad, hi(a) + pad]);
  end
  if h.ndim == 3
    view(h.axes, [130 40]);
  end
  if tdef > 1 && spadrawHasControls(f)
    h.slider = uicontrol('Parent', f, 'Style', 'slider', 'Units', 'normalized', 'Position', [0.02 0.1 0.04 0.8], ...
                         'Min', 1, 'Max', tdef, 'Value', h.step, 'SliderStep', [1 10] / (tdef - 1), ...
                         'Callback', @spadrawSlide);
  end
  set(f, 'UserData', h);
  spadrawShow(f, h.step);
end

% Whether figure f can show a slider: Octave's gnuplot toolkit draws no uicontrol (a figure holding
% one can neither be shown nor printed there).
function yes = spadrawHasControls(f)
  yes = ~(exist('graphics_toolkit') && strcmp(graphics_toolkit(f), 'gnuplot'));
end

% Slider: the nearest stored step.
function spadrawSlide(src, varargin)
  f = ancestor(src, 'figure');
  spadrawShow(f, round(get(src, 'Value')));
end

% Moves every line of figure f to stored step k and names the figure after it.
function spadrawShow(f, k)
  h = get(f, 'UserData');
  for e = 1:numel(h.lines)
    set(h.lines(e), 'XData', h.X(e, :, k), 'YData', h.Y(e, :, k));
    if h.ndim == 3
      set(h.lines(e), 'ZData', h.Z(e, :, k));
    end
  end
  h.step = k;
  set(f, 'UserData', h, 'Name', sprintf('Spacar: %s [%d/%d] t = %g', h.name, k, numel(h.time), h.time(k)));
  drawnow;
end
