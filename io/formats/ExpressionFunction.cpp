#include "io/formats/ExpressionFunction.hpp"

#include <muParser.h>

#include <cctype>
#include <limits>

namespace flexmb::io {

ExpressionFunction::ExpressionFunction(std::string expression)
    : expression_(std::move(expression)), parser_(std::make_unique<mu::Parser>()) {
  bool blank = true;
  for (char c : expression_)
    if (!std::isspace(static_cast<unsigned char>(c))) blank = false;
  if (blank) throw ExpressionError("empty expression");
  try {
    // muParser 2.3 built with GCC defines _pi as 3.141592653589 (a speed hack in
    // muParserTemplateMagic.h); redefine it to full double precision.
    parser_->DefineConst("_pi", 3.14159265358979323846264338327950288);
    parser_->DefineVar("t", &t_);
    parser_->SetExpr(expression_);
    t_ = 0.0;
    parser_->Eval();  // parses and compiles to bytecode: syntax errors surface here
    if (parser_->GetNumResults() != 1)
      throw ExpressionError("the expression gives " + std::to_string(parser_->GetNumResults()) +
                            " values (comma-separated); one is expected");
  } catch (const mu::Parser::exception_type& e) {
    throw ExpressionError(e.GetMsg());
  }
}

ExpressionFunction::~ExpressionFunction() = default;

double ExpressionFunction::value(double t) const {
  t_ = t;
  try {
    return parser_->Eval();
  } catch (const mu::Parser::exception_type&) {
    return std::numeric_limits<double>::quiet_NaN();  // compiled at construction: not expected
  }
}

core::TimeFunctionPtr ExpressionFunction::make(std::string expression) {
  return std::make_shared<const ExpressionFunction>(std::move(expression));
}

}  // namespace flexmb::io
