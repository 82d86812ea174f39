function test_spacar_toolbox(src, flexmb)
% SPACAR's toolbox around spacar() (issue 52, items 1, 2, 4): SPACAR's result names in the files
% (t beside time, de, the .sbm's ndof and nddof), loadsbd, loadsbm, checksbf, repinsbf, spadraw,
% and spacar() putting its results into the workspace from memory when a file cannot be written.
  cant = fullfile(src, 'tools', 'tests', 'data', 'cantilever_static.dat');
  copyfile(cant, 'cant.dat');
  clear t;
  r = spacar(-10, 'cant');
  check_names_in_files(r);
  assert(~exist('t', 'var'), 'spacar() put t into the workspace (SPACAR''s loadsbd makes it time)');
  check_de_fourbar(src);
  check_loadsbd(r);
  check_loadsbm();
  check_checksbf();
  check_repinsbf();
  check_spadraw_planar();
  check_spadraw_spatial(src);
  check_unwritable_files(cant, r);
  printf('test_spacar_toolbox: all checks passed\n');
end

% t = time in both files (SPACAR's spadraw reads t), de = D dx, the .sbm's ndof and nddof.
function check_names_in_files(r)
  d = load('cant.sbd', '-mat');
  m = load('cant.sbm', '-mat');
  assert(isfield(d, 't') && isequal(d.t, d.time), '.sbd: t is not time');
  assert(isfield(m, 't') && isequal(m.t, m.time), '.sbm: t is not time');
  assert(isequal(getfrsbf('cant.sbd', 't', 3), d.time(3)) && isequal(getfrsbf('cant.sbd', 'T'), d.time), 'getfrsbf t');
  assert(m.ndof == d.ndof && m.nddof == d.nddof, '.sbm: ndof, nddof');
  assert(isfield(d, 'de') && isequal(size(d.de), [d.ne d.ndof d.tdef]), '.sbd: de missing or of the wrong size');
  assert(isequal(r.de, d.de), 'spacar() struct: de');
  for k = 1:d.tdef
    err = norm(d.de(:, :, k) - d.bigd(:, :, k) * d.dx(:, :, k), 1);
    assert(err < 1e-12 * max(1, norm(d.de(:, :, k), 1)), 'de is not D dx at step %d (%g)', k, err);
  end
  % The degrees of freedom that are deformations (DYNE here): identity rows in de; fixed ones 0.
  nep = d.nep; nxp = d.nxp;
  rowsM = nep(1) + (1:nep(3) + nep(4));
  colsM = nxp(3) + nxp(4) + (1:nep(3) + nep(4));
  de3 = d.de(:, :, 3);
  assert(norm(de3(rowsM, colsM) - eye(numel(rowsM)), 1) < 1e-12, 'de of the dof deformations is not I');
  assert(norm(de3(1:nep(1), :), 1) < 1e-12, 'de of fixed deformations is not 0');
end

% de of a closed loop (mode 0 of the four-bar): rigid links, so the ground-rocker hinge angle is
% the sum of the crank angle and the two pin angles: de(e7) = 1 + de(e5) + de(e6), de(e4) = 1.
function check_de_fourbar(src)
  copyfile(fullfile(src, 'datfiles', 'tests', 'fourbar.dat'), 'fourbar.dat');
  spacar(-0, 'fourbar');
  de = getfrsbf('fourbar.sbd', 'de');
  le = getfrsbf('fourbar.sbd', 'le');
  col = getfrsbf('fourbar.sbd', 'nxp')(3:4) * [1; 1] + 1;  % the crank hinge: the only dof, a DYNE
  d4 = de(le(4, 1), col); d5 = de(le(5, 1), col); d6 = de(le(6, 1), col); d7 = de(le(7, 1), col);
  assert(abs(d4 - 1) < 1e-12, 'fourbar: de of the crank angle %g', d4);
  assert(abs(d7 - (1 + d5 + d6)) < 1e-10 && abs(d5) > 0.1, 'fourbar: loop closure of de (%g %g %g)', d5, d6, d7);
  t = getfrsbf('fourbar.sbd', 't');
  assert(isequal(t, getfrsbf('fourbar.sbd', 'time')), 'fourbar: t');
  % Mode 1 (the issue's case): getfrsbf(name.sbd, 't') is the output times.
  spacar(-1, 'fourbar', struct('tend', 0.02, 'intervals', 4));
  t = getfrsbf('fourbar.sbd', 't');
  assert(numel(t) == 5 && abs(t(end) - 0.02) < 1e-12 && isequal(t, getfrsbf('fourbar.sbd', 'time')), 'mode 1 t');
end

% loadsbd puts what spacar() put, plus mode; no t; a struct with an output; name with .sbd too.
function check_loadsbd(r)
  v = loaded_by('loadsbd', 'cant');
  names = fieldnames(r);
  for k = 1:numel(names)
    if ~any(strcmp(names{k}, {'M0', 'K0', 'G0', 'C0', 'D0', 'N0', 'freq'}))  % the .sbm's: loadsbm
      assert(isfield(v, names{k}), 'loadsbd did not create %s', names{k});
      assert(isequal(v.(names{k}), r.(names{k})), 'loadsbd: %s differs from spacar()''s', names{k});
    end
  end
  assert(isfield(v, 'mode') && v.mode == 10, 'loadsbd: mode');
  assert(~isfield(v, 't'), 'loadsbd created t (SPACAR''s loadsbd makes it time)');
  assert(isequal(v.fxtot, v.fxt), 'loadsbd: fxtot');
  w = loaded_by('loadsbd', 'cant.sbd');
  assert(isequal(w, v), 'loadsbd(''cant.sbd'') differs from loadsbd(''cant'')');
  s = loadsbd('cant');
  assert(isstruct(s) && isequal(s.x, r.x) && isfield(s, 'mode'), 'loadsbd with an output');
  try
    loadsbd('nofile');
    error('loadsbd of a missing file did not fail');
  catch err
    assert(strcmp(err.identifier, 'loadsbd:file'), 'loadsbd: %s', err.message);
  end
end

% loadsbm: SPACAR's lower-case m0 .. n0, ndof, nddof, time.
function check_loadsbm()
  v = loaded_by('loadsbm', 'cant');
  for n = {'m0', 'k0', 'g0', 'c0', 'd0', 'n0'}
    assert(isfield(v, n{1}), 'loadsbm did not create %s', n{1});
    assert(isequal(v.(n{1})(:, :, 4), getfrsbf('cant.sbm', upper(n{1}), 4)), 'loadsbm: %s', n{1});
  end
  assert(~isfield(v, 'M0') && ~isfield(v, 't'), 'loadsbm: upper-case M0 or t');
  assert(v.ndof == 6 && v.nddof == 6 && isequal(v.time, getfrsbf('cant.sbd', 'time')), 'loadsbm: counts, time');
  assert(isequal(size(v.freq), [5 6]), 'loadsbm: freq');
end

% The variables a loader creates, seen from a workspace of their own.
function v = loaded_by(loader, name__)
  feval(loader, name__);
  clear loader;
  names__ = who;
  v = struct();
  for k__ = 1:numel(names__)
    if ~any(strcmp(names__{k__}, {'name__', 'v'}))
      v.(names__{k__}) = eval(names__{k__});
    end
  end
end

% checksbf: every variable of the file, its size and how it is stored; printed without an output.
function check_checksbf()
  info = checksbf('cant.sbd');
  d = load('cant.sbd', '-mat');
  assert(isequal({info.name}', fieldnames(d)), 'checksbf: names');
  kind = @(n) info(strcmp({info.name}, n)).kind;
  assert(strcmp(kind('x'), 'rows') && strcmp(kind('t'), 'rows') && strcmp(kind('dx'), 'pages') && ...
         strcmp(kind('de'), 'pages') && strcmp(kind('lnp'), 'fixed'), 'checksbf: kinds');
  assert(isequal(info(strcmp({info.name}, 'dx')).size, [9 6 5]), 'checksbf: size of dx');
  text = evalc('checksbf(''cant.sbm'')');
  assert(~isempty(strfind(text, 'K0')) && ~isempty(strfind(text, '6 x 6 x 5')) && ...
         ~isempty(strfind(text, 'per step')), 'checksbf printed: %s', text);
end

% repinsbf: one step of a per-step variable, a page, a fixed variable, time with t; sizes checked;
% the rest of the file unchanged and readable.
function check_repinsbf()
  copyfile('cant.sbd', 'rep.sbd');
  before = load('rep.sbd', '-mat');
  xnew = (1:9) * 0.5;
  repinsbf('rep.sbd', 'X', xnew, 3);
  assert(isequal(getfrsbf('rep.sbd', 'x', 3), xnew.'), 'repinsbf: x at step 3');
  after = load('rep.sbd', '-mat');
  names = fieldnames(before);
  for k = 1:numel(names)
    if ~strcmp(names{k}, 'x')
      assert(isequal(after.(names{k}), before.(names{k})), 'repinsbf changed %s', names{k});
    end
  end
  assert(isequal(after.x([1 2 4 5], :), before.x([1 2 4 5], :)), 'repinsbf changed other steps of x');
  repinsbf('rep.sbd', 'fxtot', (1:9).', 2);  % fxtot is fxt; a column is taken too
  assert(isequal(getfrsbf('rep.sbd', 'fxt', 2), (1:9).'), 'repinsbf: fxt');
  page = magic(9)(:, 1:6);
  repinsbf('rep.sbd', 'dx', page, 5);
  assert(isequal(getfrsbf('rep.sbd', 'dx', 5), page) && isequal(getfrsbf('rep.sbd', 'dx', 4), before.dx(:, :, 4)), ...
         'repinsbf: a page of dx');
  repinsbf('rep.sbd', 'rl0', [0.25; 0.75]);
  assert(isequal(getfrsbf('rep.sbd', 'rl0'), [0.25; 0.75]), 'repinsbf: rl0');
  repinsbf('rep.sbd', 't', 7, 2);
  assert(getfrsbf('rep.sbd', 'time', 2) == 7 && getfrsbf('rep.sbd', 't', 2) == 7, 'repinsbf: time and t together');
  bad = {{'rep.sbd', 'x', 1:8, 3}, 'repinsbf:size'; {'rep.sbd', 'x', 1:9}, 'repinsbf:step';
         {'rep.sbd', 'x', 1:9, 6}, 'repinsbf:step'; {'rep.sbd', 'rl0', [1 2]}, 'repinsbf:size';
         {'rep.sbd', 'dx', ones(6, 9), 1}, 'repinsbf:size'; {'rep.sbd', 'nope', 1}, 'repinsbf:var'};
  for k = 1:rows(bad)
    try
      repinsbf(bad{k, 1}{:});
      error('repinsbf case %d did not fail', k);
    catch err
      assert(strcmp(err.identifier, bad{k, 2}), 'repinsbf case %d: %s (%s)', k, err.identifier, err.message);
    end
  end
  s = loadsbd('rep');
  assert(isequal(s.x(3, :), xnew) && isequal(s.rl0, [0.25; 0.75]), 'the replaced file read by loadsbd');
  assert(isempty(dir('rep.sbd.*')), 'repinsbf left a temporary file');
end

% spadraw of the planar cantilever: two PLBEAMs (code 5) from node 1 to 2 and 2 to 3, their ends
% at the node coordinates of every step; the figure where graphics exist, a note where not.
function check_spadraw_planar()
  set(0, 'defaultfigurevisible', 'off');
  [text, h] = evalc_spadraw('cant');
  d = load('cant.sbd', '-mat');
  assert(isequal(h.elements, [1; 2]) && isequal(h.codes, [5; 5]) && isequal(h.p, [1; 2]) && isequal(h.q, [2; 3]), ...
         'spadraw: elements');
  assert(h.ndim == 2 && isempty(h.Z) && isequal(size(h.X), [2 2 5]) && h.step == 1, 'spadraw: planar shape');
  for s = 1:5
    assert(isequal(h.X(2, :, s), d.x(s, d.lnp([2 3], 1))) && isequal(h.Y(2, :, s), d.x(s, d.lnp([2 3], 2))), ...
           'spadraw: element 2 at step %d', s);
  end
  assert(abs(h.Y(2, 2, 5) - d.x(5, d.lnp(3, 2))) == 0 && h.Y(2, 2, 5) < 0, 'spadraw: the loaded tip moves down');
  check_figure(h, text, 1);
  % oopspa's test_slidercrank.m ends with spadraw(name), no semicolon: nothing printed but a note.
  quiet = evalc('spadraw(''cant'')');
  assert(isempty(strfind(quiet, 'elements')) && isempty(strfind(quiet, 'ans')), 'spadraw(name) printed %s', quiet);
  [text, h5] = evalc_spadraw('cant.sbd', 5);
  assert(h5.step == 5, 'spadraw at step 5');
  check_figure(h5, text, 5);
  try
    spadraw('cant', 6);
    error('spadraw at step 6 of 5 did not fail');
  catch err
    assert(strcmp(err.identifier, 'spadraw:step'), 'spadraw: %s', err.message);
  end
end

% spadraw of a spatial model (the cross-spring pivot: BEAMs, code 1): three coordinates per end.
function check_spadraw_spatial(src)
  copyfile(fullfile(src, 'datfiles', 'spatial', 'cross_spring_pivot.dat'), 'pivot.dat');
  spacar(-0, 'pivot');
  d = load('pivot.sbd', '-mat');
  [text, h] = evalc_spadraw('pivot');
  beams = find(d.it == 1);
  assert(h.ndim == 3 && isequal(h.elements, beams(:)) && all(h.codes == 1), 'spadraw spatial: elements');
  for k = 1:numel(beams)
    ends = d.ln(beams(k), [1 3]);
    assert(isequal(h.Z(k, :, 1), d.x(1, d.lnp(ends, 3))), 'spadraw spatial: z of element %d', beams(k));
  end
  check_figure(h, text, 1);
end

function [text, h] = evalc_spadraw(varargin)
  h = [];
  text = evalc('h = spadraw(varargin{:});');
end

% With graphics: one line per element at the step, the slider moves them (a toolkit with uicontrols;
% the lines at another step: spadraw(name, k) above). Without graphics: a note.
function check_figure(h, text, step)
  if isempty(h.figure)
    assert(~isempty(strfind(text, 'not drawn')) && isempty(h.lines), 'spadraw without graphics said: %s', text);
    printf('test_spacar_toolbox: spadraw drew no figure here (%s)\n', strtrim(text));
    return;
  end
  assert(ishandle(h.figure) && numel(h.lines) == numel(h.elements), 'spadraw: lines');
  for k = 1:numel(h.lines)
    assert(isequal(get(h.lines(k), 'XData'), h.X(k, :, step)), 'spadraw: line %d x', k);
    assert(isequal(get(h.lines(k), 'Color'), h.color(k, :)), 'spadraw: line %d colour', k);
  end
  if numel(h.time) > 1 && isempty(h.slider)  % Octave's gnuplot toolkit draws no uicontrol
    assert(strcmp(graphics_toolkit(h.figure), 'gnuplot'), 'spadraw: no slider over %d steps', numel(h.time));
  elseif numel(h.time) > 1
    set(h.slider, 'Value', numel(h.time));
    cb = get(h.slider, 'Callback');
    cb(h.slider, []);
    assert(isequal(get(h.lines(end), 'YData'), h.Y(end, :, end)), 'spadraw: the slider did not move the lines');
  end
end

% Item 4: a result file that cannot be written (a folder of its name) is named in a warning; the
% workspace and the struct get the results from memory, equal to a run that wrote its files.
function check_unwritable_files(cant, ref)
  for stale = {'wf.sbd', 'wf.sbm', 'wg.sbd', 'wg.sbm'}  % a run before this one in the same folder
    if exist(stale{1}, 'dir')
      rmdir(stale{1});
    elseif exist(stale{1}, 'file')
      delete(stale{1});
    end
  end
  copyfile(cant, 'wf.dat');
  mkdir('wf.sbd');
  lastwarn('');
  clear x M0;
  r = spacar(-10, 'wf');
  [msg, id] = lastwarn();
  assert(strcmp(id, 'flexmb:spacar:write') && ~isempty(strfind(msg, 'wf.sbd')) && isempty(strfind(msg, 'wf.sbm')), ...
         'no warning naming wf.sbd alone: %s (%s)', msg, id);
  assert(exist('x', 'var') && isequal(x, ref.x) && isequal(M0, ref.M0), 'workspace after an unwritable .sbd');
  names = fieldnames(ref);
  for k = 1:numel(names)
    assert(isfield(r, names{k}) && isequal(r.(names{k}), ref.(names{k})), 'struct after an unwritable .sbd: %s', names{k});
  end
  assert(exist('wf.sbd', 'dir') == 7 && exist('wf.sbm', 'file') == 2, 'the .sbm beside the folder');
  assert(isequal(getfrsbf('wf.sbm', 'K0'), getfrsbf('cant.sbm', 'K0')), 'wf.sbm');
  % The .sbd written, the .sbm not.
  copyfile(cant, 'wg.dat');
  mkdir('wg.sbm');
  lastwarn('');
  clear M0 freq;
  spacar(-10, 'wg');
  [msg, id] = lastwarn();
  assert(strcmp(id, 'flexmb:spacar:write') && ~isempty(strfind(msg, 'wg.sbm')), 'no warning naming wg.sbm: %s', msg);
  assert(isequal(M0, ref.M0) && isequal(freq, ref.freq), 'workspace after an unwritable .sbm');
  assert(isequal(getfrsbf('wg.sbd', 'x'), ref.x) && exist('wg.sbm', 'dir') == 7, 'wg.sbd and the folder wg.sbm');
end
