function [stress, elements, steps, stressextrema] = stressbeam(sbdfile, elements, steps, opt, propcrossect)
% STRESSBEAM  Largest von Mises stress of beams, from a .sbd, with SPACAR's call:
%   [stress, elements, steps, stressextrema] = stressbeam('name.sbd', elements, steps, opt, propcrossect)
%   elements      element labels (BEAM, BEAMW; also PLBEAM and trusses);
%   steps         stored steps (1..tdef); [] for all;
%   opt           options struct; opt.exterior = true (the default) evaluates the exterior of the
%                 section, where beam stresses are largest (false is accepted and gives the same);
%   propcrossect  one entry per element: CrossSection 'rect' with Dimensions [w t] (w along the
%                 element's local y axis, the width SPACAR Light's orien vector points along; t along
%                 local z) or 'circ' with Dimensions d.
%   stress(i, k)  the largest von Mises stress of element i at step k, in MPa (N/mm^2, for a model
%                 in m and N), over both ends and the whole exterior of the section;
%   stressextrema.max, .min   the largest and smallest of those (MPa); .element, .step where the
%                 largest is. SPACAR Light multiplies .max by 1e6 for Pa.
%
%   Stresses from the generalised stresses sig of the .sbd (io/results.md), with the reference
%   length l0 (rl0): normal force N = sig1; BEAM torque T = l0 sig2, end bending moments
%   My = l0 sig3 (p), l0 sig4 (q), Mz = l0 sig5, l0 sig6 (core/elements: bending deformations are
%   l0 times the end rotations); BEAMW torque T = l0 (sig2 - sig7 - sig8) and bimoments
%   B_p = E Cw (4 e7 + 2 e8) / l0^3, B_q = E Cw (2 e7 + 4 e8) / l0^3 when the .sbd's stif holds
%   E Cw (its 7th column). At each end and each point (y, z) of the section's exterior:
%     normal stress  s = N/A + My z/Iy - Mz y/Iz (+ B y z/Cw, added with the sign that makes |s|
%                    largest: a bound, exact without bimoment),
%     shear stress   t from St Venant torsion: rectangle (short side h, long side b) by the exact
%                    series, on the long side  t = (T h/It) [1 - (8/pi^2) sum_n odd cosh(n pi u/h) /
%                    (n^2 cosh(n pi b/(2h)))] (u along it; its middle gives the thin-strip formula
%                    t = T h/It = 3 T/(b h^2) for b >> h), on the short side the series' other
%                    derivative; It by the same series as SPACAR Light; circle t = T (d/2)/(pi d^4/32);
%     von Mises      sqrt(s^2 + 3 t^2)  (shear from the shear forces is left out: slender beams).
  if nargin < 5
    error('stressbeam:usage', ['usage: [stress, elements, steps, stressextrema] = stressbeam(''name.sbd'', ' ...
                               'elements, steps, opt, propcrossect)']);
  end
  if ~exist(sbdfile, 'file')
    error('stressbeam:file', 'stressbeam: cannot find ''%s''', sbdfile);
  end
  s = load(sbdfile, '-mat');
  for v = {'sig', 'le', 'rl0', 'tdef'}
    if ~isfield(s, v{1})
      error('stressbeam:file', 'stressbeam: %s holds no ''%s'' (not a SPACAR result file?)', sbdfile, v{1});
    end
  end
  if isempty(steps)
    steps = 1:s.tdef;
  end
  if any(steps < 1 | steps > s.tdef | steps ~= fix(steps))
    error('stressbeam:step', 'stressbeam: steps must be integers from 1 to %d (tdef of %s)', s.tdef, sbdfile);
  end
  if numel(propcrossect) ~= numel(elements)
    error('stressbeam:usage', 'stressbeam: %d elements but %d cross-sections', numel(elements), numel(propcrossect));
  end
  stress = zeros(numel(elements), numel(steps));
  for i = 1:numel(elements)
    el = elements(i);
    if el < 1 || el > rows_(s.le) || ~any(s.le(el, :))
      error('stressbeam:element', 'stressbeam: %s has no element %d', sbdfile, el);
    end
    defs = s.le(el, s.le(el, :) > 0);
    l0 = s.rl0(el);
    sec = section(propcrossect(i), el);
    ecw = 0;
    if numel(defs) == 8 && isfield(s, 'stif') && size(s.stif, 2) >= 7
      ecw = s.stif(el, 7);
    end
    for k = 1:numel(steps)
      g = s.sig(steps(k), defs);
      switch numel(defs)
        case 1  % truss
          loads = [g(1) 0 0 0 0];
        case 3  % planar beam: in-plane bending across the second dimension
          loads = [g(1) 0 0 l0 * g(2) 0; g(1) 0 0 l0 * g(3) 0];
        case 6
          loads = [g(1) l0 * g(2) l0 * g(3) l0 * g(5) 0; g(1) l0 * g(2) l0 * g(4) l0 * g(6) 0];
        case 8
          T = l0 * (g(2) - g(7) - g(8));
          e = s.e(steps(k), defs);
          Bp = ecw * (4 * e(7) + 2 * e(8)) / l0^3;
          Bq = ecw * (2 * e(7) + 4 * e(8)) / l0^3;
          loads = [g(1) T l0 * g(3) l0 * g(5) Bp; g(1) T l0 * g(4) l0 * g(6) Bq];
        otherwise
          error('stressbeam:element', 'stressbeam: element %d has %d deformations: not a beam or truss', el, ...
                numel(defs));
      end
      if numel(defs) == 3
        loads(:, [3 4]) = loads(:, [4 3]);  % planar: the in-plane moment bends across t (about y)
      end
      vm = 0;
      for r = 1:rows_(loads)
        vm = max(vm, vonMises(sec, loads(r, :)));
      end
      stress(i, k) = vm / 1e6;
    end
  end
  [m, at] = max(stress(:));
  if isempty(m)
    m = NaN;
    at = 1;
  end
  [ie, ks] = ind2sub(size(stress), at);
  stressextrema = struct('max', m, 'min', min(stress(:)), 'element', elements(min(ie, end)), ...
                         'step', steps(min(ks, end)));
end

function n = rows_(a)
  n = size(a, 1);
end

% Section properties and the points of its exterior.
function sec = section(p, el)
  if ~isfield(p, 'CrossSection') || ~isfield(p, 'Dimensions')
    error('stressbeam:section', 'stressbeam: cross-section of element %d needs CrossSection and Dimensions', el);
  end
  d = p.Dimensions;
  switch lower(p.CrossSection)
    case 'rect'
      if numel(d) < 2 || any(d(1:2) <= 0)
        error('stressbeam:section', 'stressbeam: element %d: a rectangle needs Dimensions [w t] > 0', el);
      end
      sec.kind = 'rect';
      sec.w = d(1);
      sec.t = d(2);
      sec.A = d(1) * d(2);
      sec.Iy = d(1) * d(2)^3 / 12;
      sec.Iz = d(2) * d(1)^3 / 12;
      sec.Cw = d(1)^3 * d(2)^3 / 144;
      h = min(d(1:2));
      b = max(d(1:2));
      sec.It = torsionConstant(h, b);
      sec.h = h;
      sec.b = b;
    case 'circ'
      if isempty(d) || d(1) <= 0
        error('stressbeam:section', 'stressbeam: element %d: a circle needs Dimensions d > 0', el);
      end
      sec.kind = 'circ';
      sec.d = d(1);
      sec.A = pi * d(1)^2 / 4;
      sec.I = pi * d(1)^4 / 64;
      sec.Ip = pi * d(1)^4 / 32;
    otherwise
      error('stressbeam:section', 'stressbeam: element %d: CrossSection ''%s'' (rect or circ)', el, p.CrossSection);
  end
end

% St Venant torsion constant of an h x b rectangle (h <= b), the series SPACAR Light uses.
function It = torsionConstant(h, b)
  a = h / 2;
  c = b / 2;
  sum5 = 0;
  for n = 1:2:201
    term = tanh(n * pi * c / (2 * a)) / n^5;
    sum5 = sum5 + term;
    if n >= 3 && term < 1e-12 * sum5
      break;
    end
  end
  It = (2 * a)^3 * (2 * c) / 3 * (1 - 192 / pi^5 * (a / c) * sum5);
end

% Largest von Mises stress over the exterior; loads = [N T My Mz B].
function vm = vonMises(sec, L)
  N = L(1);
  T = L(2);
  My = L(3);
  Mz = L(4);
  B = L(5);
  if strcmp(sec.kind, 'circ')
    r = sec.d / 2;
    s = abs(N) / sec.A + hypot(My, Mz) * r / sec.I;
    t = abs(T) * r / sec.Ip;
    vm = sqrt(s^2 + 3 * t^2);
    return;
  end
  % Points along the four sides (u along the side, the side at v = +-half the other dimension).
  n = 101;
  u = linspace(-0.5, 0.5, n);
  vm = 0;
  for side = 1:2  % 1: sides z = +-t/2 (u along y), 2: sides y = +-w/2 (u along z)
    if side == 1
      y = u * sec.w;
      z = sec.t / 2 * ones(1, n);
    else
      y = sec.w / 2 * ones(1, n);
      z = u * sec.t;
    end
    tau = torsionShear(sec, T, side, side == 1 && sec.w >= sec.t || side == 2 && sec.w < sec.t, u);
    for sy = [-1 1]
      for sz = [-1 1]
        sig = N / sec.A + My * (sz * z) / sec.Iy - Mz * (sy * y) / sec.Iz;
        sig = sign(sig + (sig == 0)) .* (abs(sig) + abs(B * y .* z) / sec.Cw);
        vm = max(vm, max(sqrt(sig.^2 + 3 * tau.^2)));
      end
    end
  end
end

% |shear| of St Venant torsion along a side of the rectangle, u in [-1/2, 1/2] of its length.
% Long side (length b): Gtheta h [1 - 8/pi^2 sum cosh(n pi x/h)/(n^2 cosh(n pi b/2h))], x = u b;
% short side (length h): Gtheta (8 h/pi^2) sum (-1)^((n-1)/2) tanh(n pi b/2h) cos(n pi x/h)/n^2, x = u h.
function tau = torsionShear(sec, T, ~, longSide, u)
  if T == 0
    tau = zeros(size(u));
    return;
  end
  h = sec.h;
  b = sec.b;
  Gtheta = abs(T) / sec.It;
  acc = zeros(size(u));
  for n = 1:2:401
    if longSide
      x = u * b;
      % cosh(n pi x/h)/cosh(n pi b/2h) without overflow
      term = exp(n * pi * (abs(x) - b / 2) / h) .* (1 + exp(-2 * n * pi * abs(x) / h)) ./ ...
             (1 + exp(-n * pi * b / h)) / n^2;
    else
      x = u * h;
      term = (-1)^((n - 1) / 2) * tanh(n * pi * b / (2 * h)) * cos(n * pi * x / h) / n^2;
    end
    acc = acc + term;
    if max(abs(term)) < 1e-14 * max(max(abs(acc)), 1e-300)
      break;
    end
  end
  if longSide
    tau = Gtheta * h * (1 - 8 / pi^2 * acc);
  else
    tau = Gtheta * 8 * h / pi^2 * abs(acc);
  end
end
