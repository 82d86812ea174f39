#include "io/templates/ModelTemplate.hpp"

#include <muParser.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <deque>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace flexmb::io {

namespace {

std::string trimmed(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

bool isIdentifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// Levenshtein distance, for "did you mean" suggestions.
size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s.empty() ? "none" : s;
}

std::string quoted(const ModelTemplate::Placeholder& p) {
  if (p.kind == ModelTemplate::Placeholder::Kind::Value) return "{" + p.expression + "}";
  return "{" + p.name + (p.kind == ModelTemplate::Placeholder::Kind::Default ? " ?= " : " = ") + p.expression + "}";
}

// One muParser with a stable slot per name (muParser keeps the variables' addresses).
class Evaluator {
 public:
  Evaluator() {
    // muParser 2.3 built with GCC defines _pi to 12 digits (see ExpressionFunction.cpp).
    parser_.DefineConst("_pi", 3.14159265358979323846264338327950288);
  }
  void define(const std::string& name, double value) {
    auto it = slots_.find(name);
    if (it == slots_.end()) {
      storage_.push_back(value);
      slots_.emplace(name, &storage_.back());
      parser_.DefineVar(name, &storage_.back());
    } else {
      *it->second = value;
    }
  }
  bool defined(const std::string& name) const { return slots_.count(name) > 0; }
  // The names an expression uses (defined or not); throws mu::Parser::exception_type on syntax errors.
  std::vector<std::string> usedNames(const std::string& expression) {
    parser_.SetExpr(expression);
    std::vector<std::string> names;
    for (const auto& [name, ptr] : parser_.GetUsedVar()) names.push_back(name);
    return names;
  }
  double evaluate(const std::string& expression) {
    parser_.SetExpr(expression);
    const double v = parser_.Eval();
    if (parser_.GetNumResults() != 1)
      throw std::invalid_argument("the expression gives " + std::to_string(parser_.GetNumResults()) +
                                  " values (comma-separated); one is expected");
    return v;
  }

 private:
  mu::Parser parser_;
  std::deque<double> storage_;
  std::map<std::string, double*> slots_;
};

}  // namespace

namespace {
std::string placed(const std::string& file, int line, const std::string& message) {
  std::string s = file;
  if (line > 0) s.append(":").append(std::to_string(line));
  return s.append(": ").append(message);
}
}  // namespace

TemplateError::TemplateError(const std::string& file, int line, const std::string& message)
    : std::runtime_error(placed(file, line, message)), line_(line) {}

std::string roundTripNumber(double v) {
  char buf[64];
  // %g style: 0.0003, not 3e-04 (the shortest form), and 2.1e+11.
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general);
  return std::string(buf, r.ptr);
}

double evaluateExpression(const std::string& expression, const ParameterValues& variables) {
  Evaluator ev;
  for (const auto& [name, v] : variables) ev.define(name, v);
  try {
    for (const auto& n : ev.usedNames(expression))
      if (!ev.defined(n)) throw std::invalid_argument("unknown name '" + n + "' in " + expression);
    return ev.evaluate(expression);
  } catch (const mu::Parser::exception_type& e) {
    throw std::invalid_argument("bad expression " + expression + ": " + e.GetMsg());
  }
}

bool isParameterName(const std::string& name) {
  static const std::set<std::string> reserved = {"name", "variant", "status", "reason"};
  return isIdentifier(name) && !reserved.count(name);
}

ModelTemplate::ModelTemplate(std::string text, std::string fileName)
    : text_(std::move(text)), file_(std::move(fileName)) {
  int line = 1;
  for (size_t i = 0; i < text_.size(); ++i) {
    const char c = text_[i];
    if (c == '\n') ++line;
    if (c == '}') throw TemplateError(file_, line, "a '}' without '{' (braces in a template are placeholders only)");
    if (c != '{') continue;
    size_t j = i + 1;
    while (j < text_.size() && text_[j] != '}' && text_[j] != '{' && text_[j] != '\n') ++j;
    if (j >= text_.size() || text_[j] != '}')
      throw TemplateError(file_, line,
                          "a '{' without '}' on its line (a placeholder is {expression} on one line, no nesting)");
    Placeholder p;
    p.line = line;
    p.begin = i;
    p.end = j + 1;
    const std::string inner = trimmed(text_.substr(i + 1, j - i - 1));
    if (inner.empty()) throw TemplateError(file_, line, "an empty placeholder {}");
    // A definition: name = expr or name ?= expr (not ==, <=, >=, !=).
    size_t k = 0;
    while (k < inner.size() && (std::isalnum(static_cast<unsigned char>(inner[k])) || inner[k] == '_')) ++k;
    size_t op = k;
    while (op < inner.size() && std::isspace(static_cast<unsigned char>(inner[op]))) ++op;
    const bool isDefault = inner.compare(op, 2, "?=") == 0;
    const bool isDefine =
        !isDefault && op < inner.size() && inner[op] == '=' && (op + 1 >= inner.size() || inner[op + 1] != '=');
    if (isDefault || isDefine) {
      p.kind = isDefault ? Placeholder::Kind::Default : Placeholder::Kind::Define;
      p.name = inner.substr(0, k);
      p.expression = trimmed(inner.substr(op + (isDefault ? 2 : 1)));
      if (!isParameterName(p.name))
        throw TemplateError(file_, line,
                            "{" + inner + "}: '" + p.name +
                                "' cannot be defined (a name is a letter or '_' followed by letters, digits or '_'; "
                                "name, variant, status and reason are reserved)");
      if (p.expression.empty()) throw TemplateError(file_, line, "{" + inner + "}: no expression after the '='");
    } else {
      p.expression = inner;
    }
    placeholders_.push_back(std::move(p));
    i = j;
  }
}

ModelTemplate ModelTemplate::fromFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw TemplateError(path, 0, "cannot read the template");
  std::stringstream s;
  s << in.rdbuf();
  if (in.bad()) throw TemplateError(path, 0, "cannot read the template");
  return ModelTemplate(s.str(), path);
}

void ModelTemplate::check(const std::vector<std::string>& parameters) const {
  const std::set<std::string> given(parameters.begin(), parameters.end());
  for (const auto& name : parameters)
    if (!isParameterName(name))
      throw TemplateError(file_, 0,
                          "'" + name +
                              "' cannot be a parameter name (a letter or '_' followed by letters, digits or '_'; name, "
                              "variant, status and reason are reserved)");
  Evaluator ev;
  for (const auto& name : parameters) ev.define(name, 1.0);
  std::map<std::string, int> definedAt;  // names defined by the template, and where
  std::set<std::string> used;
  for (const auto& p : placeholders_) {
    std::vector<std::string> names;
    try {
      names = ev.usedNames(p.expression);
    } catch (const mu::Parser::exception_type& e) {
      throw TemplateError(file_, p.line, "bad expression " + quoted(p) + ": " + e.GetMsg());
    }
    for (const auto& n : names) {
      if (ev.defined(n)) {
        used.insert(n);
        continue;
      }
      std::string message =
          "unknown parameter '" + n + "' in " + quoted(p) + " (the study's parameters: " + joined(parameters);
      for (const auto& later : placeholders_)
        if (later.kind != Placeholder::Kind::Value && later.name == n && later.line >= p.line) {
          message += "; '" + n + "' is defined later, at line " + std::to_string(later.line);
          break;
        }
      std::vector<std::string> candidates = parameters;
      for (const auto& [d, l] : definedAt) candidates.push_back(d);
      for (const auto& c : candidates)
        if (editDistance(c, n) <= std::max<size_t>(1, n.size() / 3)) {
          message += "; did you mean '" + c + "'?";
          break;
        }
      throw TemplateError(file_, p.line, message + ")");
    }
    try {
      ev.evaluate(p.expression);
    } catch (const mu::Parser::exception_type& e) {
      throw TemplateError(file_, p.line, "bad expression " + quoted(p) + ": " + e.GetMsg());
    } catch (const std::exception& e) {
      throw TemplateError(file_, p.line, "bad expression " + quoted(p) + ": " + e.what());
    }
    if (p.kind == Placeholder::Kind::Value) continue;
    if (p.kind == Placeholder::Kind::Define && given.count(p.name))
      throw TemplateError(file_, p.line,
                          quoted(p) + " redefines the study parameter '" + p.name + "' (write {" + p.name +
                              " ?= " + p.expression + "} for a default the study may override)");
    if (auto it = definedAt.find(p.name); it != definedAt.end())
      throw TemplateError(file_, p.line,
                          quoted(p) + ": '" + p.name + "' is already defined at line " + std::to_string(it->second));
    if (given.count(p.name)) {
      used.insert(p.name);  // a default the study overrides: the value still enters the text
      continue;
    }
    definedAt.emplace(p.name, p.line);
    ev.define(p.name, 1.0);
  }
  for (const auto& name : parameters)
    if (!used.count(name))
      throw TemplateError(file_, 0,
                          "the parameter '" + name +
                              "' is not used by the template (no placeholder names it): every variant would be the "
                              "same model");
}

std::string ModelTemplate::instantiate(const ParameterValues& values, ParameterValues* defined) const {
  Evaluator ev;
  std::set<std::string> given;
  for (const auto& [name, v] : values) {
    ev.define(name, v);
    given.insert(name);
  }
  std::string out;
  out.reserve(text_.size() + 16 * placeholders_.size());
  size_t at = 0;
  for (const auto& p : placeholders_) {
    out.append(text_, at, p.begin - at);
    at = p.end;
    double v = 0.0;
    if (p.kind == Placeholder::Kind::Default && given.count(p.name)) {
      v = std::find_if(values.begin(), values.end(), [&](const auto& nv) { return nv.first == p.name; })->second;
    } else {
      try {
        v = ev.evaluate(p.expression);
      } catch (const mu::Parser::exception_type& e) {
        throw TemplateError(file_, p.line, "bad expression " + quoted(p) + ": " + e.GetMsg());
      } catch (const std::exception& e) {
        throw TemplateError(file_, p.line, "bad expression " + quoted(p) + ": " + e.what());
      }
      if (!std::isfinite(v)) {
        std::string where;
        for (const auto& [name, value] : values) {
          if (!where.empty()) where += ", ";
          ((where += name) += " = ") += roundTripNumber(value);
        }
        throw TemplateError(file_, p.line,
                            quoted(p) + " gives " +
                                (std::isnan(v) ? "NaN"
                                 : v > 0       ? "inf"
                                               : "-inf") +
                                " at " + where);
      }
      if (p.kind != Placeholder::Kind::Value) {
        ev.define(p.name, v);
        if (defined) defined->emplace_back(p.name, v);
      }
    }
    out += roundTripNumber(v);
  }
  out.append(text_, at, std::string::npos);
  return out;
}

}  // namespace flexmb::io
