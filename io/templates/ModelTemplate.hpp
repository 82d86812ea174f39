#pragma once
// A model template for design studies (`flexmb study`): an ordinary .dat text in which numbers may
// be written as placeholders in braces, evaluated with muParser for each variant of the study.
// SPACAR's language has no braces, so a placeholder can never be mistaken for model input.
//
//   {t}            the value of the study parameter t
//   {2.1e11*w*t}   any muParser expression in the parameters (+ - * / ^, sqrt, sin, ..., _pi,
//                  c ? a : b)
//   {EA = E*w*t}   defines EA for the placeholders after it, and stands for its value
//   {w ?= 0.05}    a default: the study's value of w where the study gives w, else 0.05
//
// Placeholders count everywhere, comments included (so a comment can record a value:
// `# t = {t} m`), and cannot span lines. Each is replaced by the shortest text that reads back as
// the same double, so the model holds exactly the value computed. Lines keep their numbers, so a
// reader's error in an instantiated model names the template's line.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace flexmb::io {

// A template error with its place: what() is "file:line: message" (line 0: "file: message").
class TemplateError : public std::runtime_error {
 public:
  TemplateError(const std::string& file, int line, const std::string& message);
  int line() const { return line_; }

 private:
  int line_;
};

// Parameter values of one variant, by name.
using ParameterValues = std::vector<std::pair<std::string, double>>;

class ModelTemplate {
 public:
  struct Placeholder {
    enum class Kind { Value, Define, Default };
    Kind kind = Kind::Value;
    int line = 0;               // 1-based
    size_t begin = 0, end = 0;  // the braces' span in the text ([begin, end), braces included)
    std::string name;           // Define / Default: the name defined
    std::string expression;     // the muParser expression
  };

  // Parses the placeholders; throws TemplateError for an unclosed '{', a '}' without '{', an empty
  // placeholder or a definition of an invalid name.
  ModelTemplate(std::string text, std::string fileName);
  static ModelTemplate fromFile(const std::string& path);  // throws TemplateError when unreadable

  const std::string& text() const { return text_; }
  const std::string& fileName() const { return file_; }
  const std::vector<Placeholder>& placeholders() const { return placeholders_; }

  // Checks the template against the study's parameter names before anything runs: every name an
  // expression uses is a parameter, a muParser constant or defined before it; every parameter is
  // used (a parameter that changes nothing is a mistake); no parameter is redefined with '='
  // (use '?=' for a default); every expression compiles. Throws TemplateError naming the line.
  void check(const std::vector<std::string>& parameters) const;

  // The model text of one variant. Throws TemplateError naming the line when an expression cannot
  // be evaluated or gives a value that is not finite (e.g. {1/(t-0.1)} at t = 0.1). `defined`, when
  // given, receives the values of the names the template defines ({A = ...}, and {w ?= ...} where
  // the study does not give w), for derived quantities.
  std::string instantiate(const ParameterValues& values, ParameterValues* defined = nullptr) const;

 private:
  std::string text_, file_;
  std::vector<Placeholder> placeholders_;
};

// The shortest decimal text in %g style that reads back as v (std::to_chars, general), e.g.
// "0.0003", "0.00015", "2.1e+11", "1.05e+06".
std::string roundTripNumber(double v);

// The value of a muParser expression in the given variables (a derived quantity of a study).
// Throws std::invalid_argument with muParser's message, naming an unknown variable.
double evaluateExpression(const std::string& expression, const ParameterValues& variables);

// Whether name can be a parameter: a letter or '_' then letters, digits or '_', and not one of
// the names the study's tables use for themselves (name, variant, status, reason).
bool isParameterName(const std::string& name);

}  // namespace flexmb::io
