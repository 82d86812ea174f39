classdef sym
% Minimal symbolic expressions for the test stand-ins syms/solve: an expression is a function of
% a struct of variable values, with the names of the variables it uses. Supports + - * / ^, unary
% minus, sin, cos, sqrt and == (an equation lhs - rhs = 0), which is what
% FlexibleInstrumentSimulation's channel geometry needs. Not a computer-algebra system.
  properties
    f     % @(v) value, v a struct with one field per variable
    vars  % cell of variable names
  end
  methods
    function s = sym(name, vars)
      if nargin == 1
        if ischar(name)
          s.f = @(v) v.(name);
          s.vars = {name};
        else
          c = double(name);
          s.f = @(v) c;
          s.vars = {};
        end
      else
        s.f = name;
        s.vars = vars;
      end
    end
    function r = plus(a, b), r = sym.bin(a, b, @plus); end
    function r = minus(a, b), r = sym.bin(a, b, @minus); end
    function r = times(a, b), r = sym.bin(a, b, @times); end
    function r = mtimes(a, b), r = sym.bin(a, b, @times); end
    function r = rdivide(a, b), r = sym.bin(a, b, @rdivide); end
    function r = mrdivide(a, b), r = sym.bin(a, b, @rdivide); end
    function r = power(a, b), r = sym.bin(a, b, @power); end
    function r = mpower(a, b), r = sym.bin(a, b, @power); end
    function r = eq(a, b), r = sym.bin(a, b, @minus); end
    function r = uminus(a), r = sym(@(v) -a.f(v), a.vars); end
    function r = sin(a), r = sym(@(v) sin(a.f(v)), a.vars); end
    function r = cos(a), r = sym(@(v) cos(a.f(v)), a.vars); end
    function r = sqrt(a), r = sym(@(v) sqrt(a.f(v)), a.vars); end
    function d = double(a)
      if ~isempty(a.vars), error('sym:double', 'sym: expression still has variables'); end
      d = a.f(struct());
    end
  end
  methods (Static)
    function r = bin(a, b, op)
      a = sym.lift(a);
      b = sym.lift(b);
      fa = a.f; fb = b.f;
      r = sym(@(v) op(fa(v), fb(v)), unique([a.vars, b.vars]));
    end
    function a = lift(a)
      if ~isa(a, 'sym'), a = sym(a); end
    end
  end
end
