function [ok, msg, varargout] = flexmb_usercall(fname, nout, varargin)
% FLEXMB_USERCALL  Used by spacar (flexmb): calls a USERSIG / USERINP function and returns its error
% message instead of raising it, so that the error ends the run cleanly.
  varargout = cell(1, nout);
  try
    [varargout{1:nout}] = feval(fname, varargin{:});
    ok = true;
    msg = '';
  catch err
    ok = false;
    msg = err.message;
    varargout = cell(1, nout);
    varargout(:) = {[]};
  end
end
