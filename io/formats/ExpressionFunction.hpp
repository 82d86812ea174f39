#pragma once
// core::TimeFunction backed by muParser (docs/theory/dat-format.md section 6): an expression in the variable
// `t` (functions sin, cos, exp, sqrt, ..., constant _pi, ternary c ? a : b). The expression is
// compiled when the object is made; evaluation reuses muParser's bytecode and only writes `t`.
// value() is const but not thread-safe: one evaluation at a time per object.
#include <memory>
#include <stdexcept>
#include <string>

#include "core/model/TimeFunction.hpp"

namespace mu {
class Parser;
}

namespace flexmb::io {

// A syntax error, an unknown variable or an expression with several results. what() is muParser's
// message (the reader adds file:line and the keyword).
class ExpressionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ExpressionFunction final : public core::TimeFunction {
 public:
  explicit ExpressionFunction(std::string expression);  // throws ExpressionError
  ~ExpressionFunction() override;
  ExpressionFunction(const ExpressionFunction&) = delete;  // muParser holds the address of t_
  ExpressionFunction& operator=(const ExpressionFunction&) = delete;

  double value(double t) const override;
  std::string text() const override { return expression_; }

  // Compiles `expression` into a shared TimeFunction (throws ExpressionError).
  static core::TimeFunctionPtr make(std::string expression);

 private:
  std::string expression_;
  mutable double t_ = 0.0;
  std::unique_ptr<mu::Parser> parser_;  // Eval() mutates its stack: used from const value()
};

}  // namespace flexmb::io
