function h = spavisual(name, varargin)
% SPAVISUAL  flexmb's picture of a model, in place of SPACAR's viewer.
%   h = spavisual(name)   draws name.dat with flexmb (`flexmb show`: node and element numbers,
%                         fixed, input and free nodes, a table of the roles) into name_model.svg,
%                         prints where it is and returns at once: nothing opens and nothing waits,
%                         so it runs headless and never blocks a script.
%   h is a struct, not a figure handle: h.file is the picture, h.Children.XLabel.String (and
%   YLabel, ZLabel) are there so that scripts that label SPACAR's figure (SPACAR Light:
%   results.fighandle.Children.XLabel.String = 'x') run unchanged. An empty h.file means no
%   picture could be made (h.message says why); that is a note, not an error.
%   The flexmb program is the one beside this folder (build/flexmb for build/octave), or the one
%   the environment variable FLEXMB names.
  if nargin < 1 || ~ischar(name)
    error('spavisual:usage', 'usage: h = spavisual(name)');
  end
  if numel(name) > 4 && strcmpi(name(end-3:end), '.dat')
    name = name(1:end-4);
  end
  label = struct('String', '');
  h = struct('file', '', 'message', '', 'Children', struct('XLabel', label, 'YLabel', label, 'ZLabel', label));
  exe = getenv('FLEXMB');
  if isempty(exe)
    exe = fullfile(fileparts(mfilename('fullpath')), '..', 'flexmb');
  end
  dat = [name '.dat'];
  out = [name '_model.svg'];
  if ~exist(dat, 'file')
    h.message = sprintf('no model file %s', dat);
  elseif ~exist(exe, 'file')
    h.message = sprintf('the flexmb program was not found at %s (set FLEXMB)', exe);
  else
    [status, text] = system(sprintf('"%s" show "%s" --out "%s" 2>&1', exe, dat, out));
    if status == 0
      h.file = out;
    else
      h.message = strtrim(text);
    end
  end
  if isempty(h.file)
    fprintf('spavisual: no picture of %s: %s\n', name, h.message);
  else
    fprintf('spavisual: flexmb''s picture of %s is %s\n', name, fullfile(pwd, h.file));
  end
end
