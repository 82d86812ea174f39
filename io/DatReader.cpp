#include "io/DatReader.hpp"

#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/ModelBuilder.hpp"
#include "io/ExpressionFunction.hpp"
#include "io/KeywordTable.hpp"

namespace flexmb::io {

namespace {

std::string formatWhat(const std::string& file, int line, const std::string& keyword,
                       const std::string& message) {
  std::ostringstream o;
  o << file;
  if (line > 0) o << ':' << line;
  o << ": ";
  if (!keyword.empty()) o << keyword << ": ";
  o << message;
  return o.str();
}

}  // namespace

DatError::DatError(std::string file, int line, std::string keyword, std::string message)
    : std::runtime_error(formatWhat(file, line, keyword, message)),
      file_(std::move(file)),
      line_(line),
      keyword_(std::move(keyword)),
      message_(std::move(message)) {}

core::ElongationDefinition defaultElongation(core::Dialect d) {
  return d == core::Dialect::Spacar95 ? core::ElongationDefinition::Plain
                                      : core::ElongationDefinition::BendingCorrected;
}

const char* dialectName(core::Dialect d) {
  return d == core::Dialect::Spacar95 ? "SPACAR95" : "SPACAR 2013+";
}

namespace {

constexpr size_t kMaxKeywordLength = 8;

struct Token {
  std::string text;
  bool quoted = false;
};

struct Statement {
  int line = 0;
  std::string keyword;  // upper case
  std::vector<Token> args;
  const KeywordInfo* info = nullptr;
};

std::string upper(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return r;
}

// Shortens a token for messages (binary garbage, very long words).
std::string show(const std::string& s) {
  std::string r;
  for (unsigned char c : s) {
    if (r.size() >= 40) {
      r += "...";
      break;
    }
    if (c < 0x20 || c == 0x7f) {
      static const char* hex = "0123456789abcdef";
      r += "\\x";
      r += hex[c >> 4];
      r += hex[c & 15];
    } else {
      r += static_cast<char>(c);
    }
  }
  return "'" + r + "'";
}

std::string showToken(const Token& t) {
  return t.quoted ? "the quoted string \"" + show(t.text).substr(1, show(t.text).size() - 2) + "\""
                  : show(t.text);
}

bool isSeparator(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' || c == ',';
}
bool isCommentStart(char c) { return c == '%' || c == '#' || c == ';'; }

// Integers: [+-]digits. Reals: [+-](digits[.digits]|.digits)([eEdD][+-]digits).
enum class NumParse { Ok, NotANumber, OutOfRange };

NumParse parseInt(const std::string& s, long long& out) {
  size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  if (i == s.size()) return NumParse::NotANumber;
  for (size_t j = i; j < s.size(); ++j)
    if (!std::isdigit(static_cast<unsigned char>(s[j]))) return NumParse::NotANumber;
  size_t first = i;
  while (first + 1 < s.size() && s[first] == '0') ++first;
  if (s.size() - first > 10) return NumParse::OutOfRange;
  long long v = 0;
  for (size_t j = first; j < s.size(); ++j) v = v * 10 + (s[j] - '0');
  if (s[0] == '-') v = -v;
  if (v > INT_MAX || v < INT_MIN) return NumParse::OutOfRange;
  out = v;
  return NumParse::Ok;
}

NumParse parseReal(const std::string& s, double& out) {
  size_t i = 0;
  std::string norm;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) {
    if (s[i] == '-') norm += '-';
    ++i;
  }
  size_t digits = 0;
  while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) norm += s[i++], ++digits;
  if (i < s.size() && s[i] == '.') {
    norm += s[i++];
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) norm += s[i++], ++digits;
  }
  if (digits == 0) return NumParse::NotANumber;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E' || s[i] == 'd' || s[i] == 'D')) {
    norm += 'e';
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) norm += s[i++];
    size_t expDigits = 0;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) norm += s[i++], ++expDigits;
    if (expDigits == 0) return NumParse::NotANumber;
  }
  if (i != s.size()) return NumParse::NotANumber;
  double v = 0.0;
  const auto res = std::from_chars(norm.data(), norm.data() + norm.size(), v);
  if (res.ec == std::errc::result_out_of_range) {
    // Underflow to zero is harmless; overflow is not.
    const auto epos = norm.find('e');
    if (epos != std::string::npos && norm.size() > epos + 1 && norm[epos + 1] == '-') {
      out = 0.0;
      return NumParse::Ok;
    }
    return NumParse::OutOfRange;
  }
  if (res.ec != std::errc() || res.ptr != norm.data() + norm.size()) return NumParse::NotANumber;
  if (!std::isfinite(v)) return NumParse::OutOfRange;
  out = v;
  return NumParse::Ok;
}

// The structural pass: lexing, keyword recognition and block structure.
class Reader {
 public:
  Reader(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {}

  [[noreturn]] void fail(int line, const std::string& keyword, const std::string& message) const {
    throw DatError(file_, line, keyword, message);
  }

  void scan();
  core::Dialect detect() const;
  core::Model build(const ReadOptions& options);

 private:
  bool lexLine(std::string_view line, int lineNo, std::vector<Token>& tokens) const;
  void checkArgs(const Statement& s, const std::vector<ArgSpec>& layout) const;
  std::optional<std::string> layoutError(const Statement& s, const std::vector<ArgSpec>& layout) const;
  void apply(const Statement& s, core::ModelBuilder& b, bool spacar95);

  int integer(const Statement& s, size_t k) const;
  double real(const Statement& s, size_t k) const;
  std::optional<double> optReal(const Statement& s, size_t k) const {
    if (k < s.args.size()) return real(s, k);
    return std::nullopt;
  }
  core::TimeFunctionPtr function(const Statement& s, size_t k, const std::string& what) const;

  std::string_view text_;
  std::string file_;
  std::vector<Statement> statements_;
  int lastLine_ = 0;
  // Settings bookkeeping for the final consistency checks.
  int timestepLine_ = 0, timeLine_ = 0;
  int kinematicEndLine_ = 0;
};

bool Reader::lexLine(std::string_view line, int lineNo, std::vector<Token>& tokens) const {
  tokens.clear();
  if (!line.empty() && line[0] == '*') return false;
  size_t i = 0;
  while (i < line.size()) {
    const char c = line[i];
    if (isSeparator(c)) {
      ++i;
    } else if (isCommentStart(c)) {
      break;
    } else if (c == '"') {
      const size_t close = line.find('"', i + 1);
      if (close == std::string_view::npos) {
        const std::string kw = tokens.empty() ? "" : upper(tokens.front().text);
        fail(lineNo, kw.size() <= 16 ? kw : "", "unterminated quoted string (a '\"' without its closing '\"')");
      }
      tokens.push_back({std::string(line.substr(i + 1, close - i - 1)), true});
      i = close + 1;
    } else {
      size_t j = i;
      while (j < line.size() && !isSeparator(line[j]) && !isCommentStart(line[j]) && line[j] != '"') ++j;
      tokens.push_back({std::string(line.substr(i, j - i)), false});
      i = j;
    }
  }
  return !tokens.empty();
}

void Reader::scan() {
  // Block state: the kinematic block is open from the start; after an END no block is open until
  // the next ordinary keyword opens one.
  bool open = true;
  int closed = 0;          // number of blocks closed by END
  int openedAt = 0;        // line of the first statement of the open block
  int kinematicEndLine = 0;
  bool haltSeen = false;
  bool any = false;
  bool done = false;

  size_t pos = text_.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // a UTF-8 byte order mark
  int lineNo = 0;
  std::vector<Token> tokens;
  while (pos < text_.size() && !done) {
    size_t nl = text_.find('\n', pos);
    if (nl == std::string_view::npos) nl = text_.size();
    std::string_view line = text_.substr(pos, nl - pos);
    pos = nl + 1;
    ++lineNo;
    lastLine_ = lineNo;
    if (!lexLine(line, lineNo, tokens)) continue;

    const Token& first = tokens.front();
    if (first.quoted)
      fail(lineNo, "", "expected a keyword at the start of the line, found " + showToken(first));
    const std::string& word = first.text;
    if (!std::isalpha(static_cast<unsigned char>(word[0]))) {
      std::string msg = "expected a keyword at the start of the line, found " + show(word);
      if (word[0] == '*') msg += " (a '*' comment must start in column 1)";
      fail(lineNo, "", msg);
    }
    for (char ch : word)
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_')
        fail(lineNo, "", "invalid keyword " + show(word) +
                             " (a keyword is letters and digits, followed by blank-separated "
                             "arguments)");
    const std::string name = upper(word);
    const std::vector<const KeywordInfo*> infos = findKeywords(name);
    if (infos.empty()) {
      const std::string suggestion = suggestKeyword(name);
      const std::string hint = suggestion.empty() ? "" : "; did you mean " + suggestion + "?";
      if (name.size() > kMaxKeywordLength)
        fail(lineNo, "", "keyword " + show(word) + " is longer than 8 characters" + hint);
      fail(lineNo, "", "unknown keyword " + show(word) + hint);
    }
    any = true;
    const KeywordInfo* info = infos.front();
    if (info->action == Action::Unsupported)
      fail(lineNo, name, "SPACAR keyword not supported by flexmb yet (" + info->meaning + "); " +
                             info->unsupportedNote);

    Statement st;
    st.line = lineNo;
    st.keyword = name;
    st.args.assign(tokens.begin() + 1, tokens.end());

    const auto noArgs = [&] {
      if (!st.args.empty())
        fail(lineNo, name, "expected no arguments, found " + std::to_string(st.args.size()));
    };
    const std::string blockName = closed == 0 ? "kinematic block" : "dynamic block";
    switch (info->action) {
      case Action::End:
        noArgs();
        if (!open) {  // an empty block: END END ends the input
          done = true;
        } else {
          open = false;
          if (closed == 0) kinematicEndLine = kinematicEndLine_ = lineNo;
          ++closed;
        }
        continue;
      case Action::Halt:
        noArgs();
        if (open)
          fail(lineNo, name, "inside the " + blockName + " (begun at line " +
                                 std::to_string(openedAt) + "): missing END");
        if (closed == 1 && !haltSeen) {
          haltSeen = true;  // END HALT after the kinematic block: a separator
        } else {
          done = true;
        }
        continue;
      case Action::Eof:
      case Action::Visualization:
        if (open)
          fail(lineNo, name, "inside the " + blockName + " (begun at line " +
                                 std::to_string(openedAt) + "): missing END");
        done = true;
        continue;
      default:
        break;
    }

    if (!open) {
      open = true;
      openedAt = lineNo;
    } else if (openedAt == 0) {
      openedAt = lineNo;
    }
    const BlockKind block = closed == 0 ? BlockKind::Kinematic : BlockKind::Dynamic;
    st.info = findKeyword(name, block);
    if (!st.info) {
      if (block == BlockKind::Dynamic)
        fail(lineNo, name, "belongs to the kinematic block, which ended with END at line " +
                               std::to_string(kinematicEndLine));
      fail(lineNo, name, "belongs to a dynamic/static block, after the kinematic block's END (is the "
                         "END missing?)");
    }
    statements_.push_back(std::move(st));
  }
  if (!any) {
    if (lastLine_ == 0) fail(0, "", "the file is empty");
    fail(0, "", "the file holds no statements (only comments or blank lines)");
  }
  if (open && !done)
    fail(lastLine_, "", std::string("end of file inside the ") +
                            (closed == 0 ? "kinematic block" : "dynamic block") + " (begun at line " +
                            std::to_string(openedAt) + "): missing END");
}

core::Dialect Reader::detect() const {
  const Statement *s95 = nullptr, *s13 = nullptr;
  for (const Statement& s : statements_) {
    if (s.info->dialects == kSpacar95 && !s95) s95 = &s;
    if (s.info->dialects == kSpacar2013 && !s13) s13 = &s;
  }
  if (s95 && s13) {
    const Statement* later = s95->line > s13->line ? s95 : s13;
    fail(later->line, later->keyword,
         "the file mixes the dialects: " + s95->keyword + " (line " + std::to_string(s95->line) +
             ") is SPACAR95 only, " + s13->keyword + " (line " + std::to_string(s13->line) +
             ") is SPACAR 2013+ only");
  }
  return s95 ? core::Dialect::Spacar95 : core::Dialect::Spacar2013;
}

std::optional<std::string> Reader::layoutError(const Statement& s,
                                               const std::vector<ArgSpec>& layout) const {
  const int n = static_cast<int>(s.args.size());
  const int lo = KeywordInfo::minArgs(layout), hi = KeywordInfo::maxArgs(layout);
  if (n < lo || (hi >= 0 && n > hi))
    return KeywordInfo::expectation(layout) + ", found " + std::to_string(n);
  for (size_t k = 0; k < s.args.size(); ++k) {
    const ArgSpec& spec = k < layout.size() ? layout[k] : layout.back();
    const Token& t = s.args[k];
    switch (spec.type) {
      case ArgType::Node:
      case ArgType::Element:
      case ArgType::Component:
      case ArgType::Count: {
        if (t.quoted)
          return "expected an integer for " + spec.name + ", found " + showToken(t);
        long long v = 0;
        const NumParse p = parseInt(t.text, v);
        if (p == NumParse::OutOfRange)
          return "integer out of range for " + spec.name + ": " + show(t.text);
        if (p != NumParse::Ok) return "expected an integer for " + spec.name + ", found " + show(t.text);
        if (v <= 0)
          return "expected a positive integer for " + spec.name + ", found " + show(t.text);
        break;
      }
      case ArgType::Real: {
        if (t.quoted) return "expected a number for " + spec.name + ", found " + showToken(t);
        double v = 0.0;
        const NumParse p = parseReal(t.text, v);
        if (p == NumParse::OutOfRange)
          return "number out of range for " + spec.name + ": " + show(t.text);
        if (p != NumParse::Ok) return "expected a number for " + spec.name + ", found " + show(t.text);
        break;
      }
      case ArgType::Expression:
        if (!t.quoted)
          return "expected a quoted expression for " + spec.name + ", found " + show(t.text) +
                 " (write expressions in double quotes)";
        break;
    }
  }
  return std::nullopt;
}

void Reader::checkArgs(const Statement& s, const std::vector<ArgSpec>& layout) const {
  if (auto err = layoutError(s, layout)) fail(s.line, s.keyword, *err);
}

int Reader::integer(const Statement& s, size_t k) const {
  long long v = 0;
  if (k >= s.args.size() || parseInt(s.args[k].text, v) != NumParse::Ok)
    fail(s.line, s.keyword, "internal: integer argument " + std::to_string(k + 1) + " missing");
  return static_cast<int>(v);
}

double Reader::real(const Statement& s, size_t k) const {
  double v = 0.0;
  if (k >= s.args.size() || parseReal(s.args[k].text, v) != NumParse::Ok)
    fail(s.line, s.keyword, "internal: real argument " + std::to_string(k + 1) + " missing");
  return v;
}

core::TimeFunctionPtr Reader::function(const Statement& s, size_t k, const std::string& what) const {
  if (k >= s.args.size()) return nullptr;
  try {
    return ExpressionFunction::make(s.args[k].text);
  } catch (const ExpressionError& e) {
    fail(s.line, s.keyword, "invalid expression for " + what + " \"" + s.args[k].text + "\": " + e.what());
  }
}

void Reader::apply(const Statement& s, core::ModelBuilder& b, bool spacar95) {
  const KeywordInfo& info = *s.info;
  const auto& layout = info.layout(spacar95);
  if (info.action == Action::TimeStep) {
    if (auto err = layoutError(s, layout)) {
      std::string msg = *err;
      if (!layoutError(s, info.layout(!spacar95)))
        msg += spacar95 ? " (read as SPACAR95, TIMESTEP n T; the SPACAR 2013+ order T n would fit)"
                        : " (read as SPACAR 2013+, TIMESTEP T n; the SPACAR95 order n T would fit: "
                          "is this a SPACAR95 file? the dialect option overrides detection)";
      fail(s.line, s.keyword, msg);
    }
  } else {
    checkArgs(s, layout);
  }
  const int line = s.line;
  auto ints = [&](size_t from) {
    std::vector<int> v;
    for (size_t k = from; k < s.args.size(); ++k) v.push_back(integer(s, k));
    return v;
  };
  auto reals = [&](size_t from) {
    std::vector<double> v;
    for (size_t k = from; k < s.args.size(); ++k) v.push_back(real(s, k));
    return v;
  };
  auto positive = [&](double v, const std::string& what) {
    if (!(v > 0.0)) {
      std::ostringstream o;
      o << what << " must be positive, found " << v;
      fail(line, s.keyword, o.str());
    }
    return v;
  };
  using core::Role;
  core::AnalysisSettings& set = b.settings();
  switch (info.action) {
    case Action::Element: {
      const size_t nn = info.elementType->slots.size();
      std::vector<int> nodes;
      for (size_t k = 1; k <= nn && k < s.args.size(); ++k) nodes.push_back(integer(s, k));
      if (info.elementType->vector.empty()) {
        b.addElement(*info.elementType, integer(s, 0), nodes, line);
      } else {
        b.addElement(*info.elementType, integer(s, 0), nodes, reals(1 + nn), line);
      }
      break;
    }
    case Action::Coordinates:
    case Action::CoordinatesXY:
    case Action::CoordinatesBeta: b.setCoordinates(integer(s, 0), reals(1), line); break;
    case Action::Fix: b.setCoordinateRole(integer(s, 0), ints(1), Role::Fixed, line); break;
    case Action::InputXRole: b.setCoordinateRole(integer(s, 0), ints(1), Role::Input, line); break;
    case Action::DynX: b.setCoordinateRole(integer(s, 0), ints(1), Role::Dynamic, line); break;
    case Action::DynE: b.setDeformationRole(integer(s, 0), ints(1), Role::Dynamic, line); break;
    case Action::Rlse: b.setDeformationRole(integer(s, 0), ints(1), Role::Calculable, line); break;
    case Action::InputERole: b.setDeformationRole(integer(s, 0), ints(1), Role::Input, line); break;
    case Action::LumpedMass:
      if (s.args.size() > 2) b.setNodeInertia(integer(s, 0), reals(1), line);  // spatial tensor
      else b.setLumpedMass(integer(s, 0), real(s, 1), line);
      break;
    case Action::ElementInertia:
      b.setElementInertia(integer(s, 0), reals(1), line);  // layout by element type
      break;
    case Action::Stiffness: b.setStiffness(integer(s, 0), reals(1), line); break;
    case Action::Damping: b.setDamping(integer(s, 0), reals(1), line); break;
    case Action::Force: b.addForce(integer(s, 0), reals(1), line); break;
    case Action::ForceIncrement: b.addForceIncrement(integer(s, 0), reals(1), line); break;
    case Action::Gravity: b.setGravity(real(s, 0), real(s, 1), optReal(s, 2).value_or(0.0), line); break;
    case Action::InputXValues:
      b.setInputCoordinate(integer(s, 0), integer(s, 1), real(s, 2), optReal(s, 3), optReal(s, 4), line);
      break;
    case Action::InputEValues:
      b.setInputDeformation(integer(s, 0), integer(s, 1), real(s, 2), optReal(s, 3), optReal(s, 4), line);
      break;
    case Action::XD:
      b.setInputCoordinate(integer(s, 0), integer(s, 1), std::nullopt, real(s, 2), std::nullopt, line);
      break;
    case Action::XDD:
      b.setInputCoordinate(integer(s, 0), integer(s, 1), std::nullopt, std::nullopt, real(s, 2), line);
      break;
    case Action::E:
      b.setInitialDeformation(integer(s, 0), integer(s, 1), real(s, 2), std::nullopt, std::nullopt, line);
      break;
    case Action::ED:
      b.setInitialDeformation(integer(s, 0), integer(s, 1), std::nullopt, real(s, 2), std::nullopt, line);
      break;
    case Action::EDD:
      b.setInitialDeformation(integer(s, 0), integer(s, 1), std::nullopt, std::nullopt, real(s, 2), line);
      break;
    case Action::StartDE:
      b.setInitialDeformation(integer(s, 0), integer(s, 1), real(s, 2), optReal(s, 3), std::nullopt, line);
      break;
    case Action::InputIncrement: b.setInputIncrement(integer(s, 0), integer(s, 1), real(s, 2), line); break;
    case Action::Prestress: b.setPrestress(integer(s, 0), integer(s, 1), real(s, 2), line); break;
    case Action::TimeStep:
      if (spacar95) {
        set.outputIntervals = integer(s, 0);
        set.tEnd = real(s, 1);
      } else {
        set.tEnd = real(s, 0);
        set.outputIntervals = integer(s, 1);
      }
      set.timestepGiven = true;
      timestepLine_ = line;
      break;
    case Action::EpsInt:
      set.relTol = set.absTol = positive(real(s, 0), "the integration tolerance");
      break;
    case Action::ErrorTol:
      set.absTol = positive(real(s, 0), "the absolute tolerance");
      set.relTol = positive(real(s, 1), "the relative tolerance");
      break;
    case Action::HMax: set.hmax = positive(real(s, 0), "the maximum step size"); break;
    case Action::EpsKin: set.kinematicTol = positive(real(s, 0), "the kinematic tolerance"); break;
    case Action::MaxIterat: set.maxIterations = integer(s, 0); break;
    case Action::IterStep:
      set.maxIterations = integer(s, 0);
      set.loadSteps = integer(s, 1);
      if (auto tol = optReal(s, 2)) set.kinematicTol = positive(*tol, "the tolerance");
      break;
    case Action::Time:
      set.t0 = real(s, 0);
      timeLine_ = line;
      break;
    case Action::TimeForce: b.addTimeForce(integer(s, 0), integer(s, 1), function(s, 2, "f(t)"), line); break;
    case Action::TimeStress:
      b.addTimeStress(integer(s, 0), integer(s, 1), function(s, 2, "sigma(t)"), line);
      break;
    case Action::Reference: b.setReference(integer(s, 0), integer(s, 1), function(s, 2, "eref(t)"), line); break;
    case Action::InputXFunctions:
      b.setInputCoordinateFunctions(integer(s, 0), integer(s, 1), function(s, 2, "x(t)"),
                                    function(s, 3, "v(t)"), function(s, 4, "a(t)"), line);
      break;
    case Action::InputEFunctions:
      b.setInputDeformationFunctions(integer(s, 0), integer(s, 1), function(s, 2, "e(t)"),
                                     function(s, 3, "v(t)"), function(s, 4, "a(t)"), line);
      break;
    case Action::End:
    case Action::Halt:
    case Action::Eof:
    case Action::Visualization:
    case Action::Unsupported: fail(line, s.keyword, "internal: unexpected statement"); break;
  }
}

core::Model Reader::build(const ReadOptions& options) {
  scan();
  const core::Dialect dialect = options.dialect ? *options.dialect : detect();
  const bool spacar95 = dialect == core::Dialect::Spacar95;
  core::ModelBuilder b(file_);
  b.setDialect(dialect);
  std::map<int, std::string> keywordAt;
  bool anyElement = false;
  int kinematicLast = kinematicEndLine_;
  const Statement* current = nullptr;
  try {
    for (const Statement& s : statements_) {
      current = &s;
      keywordAt[s.line] = s.keyword;
      if (s.info->action == Action::Element) anyElement = true;
      apply(s, b, spacar95);
    }
    current = nullptr;
    const core::AnalysisSettings& set = b.settings();
    if (set.timestepGiven && !(set.tEnd > set.t0)) {
      std::ostringstream o;
      o << "the end time " << set.tEnd << " must be larger than the start time " << set.t0;
      fail(timestepLine_, "TIMESTEP", o.str());
    }
    if (!set.timestepGiven && timeLine_ && !(set.tEnd > set.t0)) {
      std::ostringstream o;
      o << "the start time " << set.t0 << " is not before the default end time " << set.tEnd
        << " (give TIMESTEP)";
      fail(timeLine_, "TIME", o.str());
    }
    if (!anyElement)
      fail(kinematicLast, kinematicLast ? "END" : "",
           "the model defines no elements (the kinematic block needs at least one)");
    core::ElementOptions eo;
    eo.elongation = options.elongation ? *options.elongation : defaultElongation(dialect);
    return b.finalize(eo);
  } catch (const DatError&) {
    throw;
  } catch (const core::ModelError& e) {
    const auto it = keywordAt.find(e.line());
    throw DatError(file_, e.line(), it == keywordAt.end() ? "" : it->second, e.what());
  } catch (const std::exception& e) {
    // Safety net: nothing but DatError leaves the reader.
    throw DatError(file_, current ? current->line : 0, current ? current->keyword : "",
                   std::string("internal error: ") + e.what());
  }
}

}  // namespace

core::Model readDatString(std::string_view text, const std::string& virtualFileName,
                          const ReadOptions& options) {
  Reader r(text, virtualFileName);
  return r.build(options);
}

core::Dialect detectDialect(std::string_view text, const std::string& virtualFileName) {
  Reader r(text, virtualFileName);
  r.scan();
  return r.detect();
}

core::Model readDatFile(const std::string& path, const ReadOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw DatError(path, 0, "", "cannot read '" + path + "': it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw DatError(path, 0, "", "cannot open '" + path + "': no such file or not readable");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw DatError(path, 0, "", "cannot read '" + path + "'");
  const std::string text = ss.str();
  return readDatString(text, path, options);
}

}  // namespace flexmb::io
