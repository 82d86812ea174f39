#include "io/formats/DatReader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/model/ModelBuilder.hpp"
#include "io/formats/ExpressionFunction.hpp"
#include "io/formats/KeywordTable.hpp"
#include "io/formats/MeshRefinement.hpp"
#include "io/formats/Visualization.hpp"

namespace flexmb::io {

namespace {

std::string formatWhat(const std::string& file, int line, const std::string& keyword, const std::string& message) {
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

const char* dialectName(core::Dialect d) { return d == core::Dialect::Spacar95 ? "SPACAR95" : "SPACAR 2013+"; }

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
  const KeywordInfo* info = nullptr;  // resolved once the dialect is known
  int block = 0;                      // 0-based index of the block (closed by END) it is in
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
  return t.quoted ? "the quoted string \"" + show(t.text).substr(1, show(t.text).size() - 2) + "\"" : show(t.text);
}

// A comma is not a separator: SPACAR's writers separate fields by blanks and tabs, and a comma
// in a number is almost always a decimal comma (-9,81), reported as such.
bool isSeparator(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
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

NumParse parseReal(const std::string& s, double& out);

// An integer field: digits, or a whole number written with decimals or an exponent (SPACAR Light
// and MATLAB writers print 1000.000000); a non-whole value (2.5) is not an integer.
NumParse parseWhole(const std::string& s, long long& out) {
  const NumParse p = parseInt(s, out);
  if (p != NumParse::NotANumber) return p;
  double v = 0.0;
  const NumParse r = parseReal(s, v);
  if (r != NumParse::Ok) return r;
  if (v != std::floor(v)) return NumParse::NotANumber;
  if (v > INT_MAX || v < INT_MIN) return NumParse::OutOfRange;
  out = static_cast<long long>(v);
  return NumParse::Ok;
}

// "-9,81" or "1,5e3": a number with a decimal comma (and at most one comma).
bool looksLikeDecimalComma(const std::string& s) {
  const auto c = s.find(',');
  if (c == std::string::npos || s.find(',', c + 1) != std::string::npos) return false;
  std::string t = s;
  t[c] = '.';
  double v = 0.0;
  return parseReal(t, v) == NumParse::Ok;
}

std::string commaHint(const std::string& s) {
  if (s.find(',') == std::string::npos) return "";
  if (looksLikeDecimalComma(s)) {
    std::string t = s;
    t[t.find(',')] = '.';
    return " (a decimal comma? write " + t + ": the decimal separator is '.', fields are separated by blanks)";
  }
  return " (fields are separated by blanks, not commas)";
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
  // The keyword that starts a line (its upper-case name in `name`); fails naming the line.
  const KeywordInfo* lineKeyword(const std::vector<Token>& tokens, int lineNo, std::string& name) const;
  // VISUALIZATION after the end of the input (SPACAR Light writes it after END END), from `pos`.
  void findVisualizationAfterEnd(size_t pos, int lineNo);
  core::Dialect detect() const;
  std::vector<AnalysisStage> build(const ReadOptions& options);

 private:
  bool lexLine(std::string_view line, int lineNo, std::vector<Token>& tokens) const;
  void resolve(Statement& s, bool spacar95) const;
  void checkArgs(const Statement& s, const std::vector<ArgSpec>& layout) const;
  std::optional<std::string> layoutError(const Statement& s, const std::vector<ArgSpec>& layout) const;
  void apply(const Statement& s, core::ModelBuilder& b, bool spacar95);
  // The run settings' statements (TIMESTEP, ERROR, ITERSTEP, ..., USERSIG): true when s was one.
  bool applySetting(const Statement& s, core::ModelBuilder& b, bool spacar95);
  void checkLayout(const Statement& s, bool spacar95) const;

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
  std::vector<int> endLines_;  // line of the END closing block k
  int lastLine_ = 0;
  // The mode-9 transfer block after END HALT: its statements, resolved into the last stage's
  // model (Model::transferInputs / transferOutputs) once the roles are known.
  int transferFirst_ = 0;
  std::vector<Statement> transfer_;
  void resolveTransfer(core::Model& model) const;
  size_t visualizationAt_ = std::string_view::npos;  // text offset after the VISUALIZATION line
  int visualizationLine_ = 0;                        // the line after it
  // Per block: the SPACAR95 TIMESTEP period (the end time is TIME + period at the block's END).
  std::optional<double> period_;
  int timestepLine_ = 0, timeLine_ = 0;
  std::string userStress_, userInput_;  // USERSIG / USERINP function names
  int userStressLine_ = 0, userInputLine_ = 0;
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

const KeywordInfo* Reader::lineKeyword(const std::vector<Token>& tokens, int lineNo, std::string& name) const {
  const Token& first = tokens.front();
  if (first.quoted) fail(lineNo, "", "expected a keyword at the start of the line, found " + showToken(first));
  const std::string& word = first.text;
  if (!std::isalpha(static_cast<unsigned char>(word[0]))) {
    std::string msg = "expected a keyword at the start of the line, found " + show(word);
    if (word[0] == '*') msg += " (a '*' comment must start in column 1)";
    fail(lineNo, "", msg);
  }
  for (char ch : word)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_')
      fail(lineNo, "",
           "invalid keyword " + show(word) +
               " (a keyword is letters and digits, followed by blank-separated "
               "arguments)" +
               (word.find(',') != std::string::npos ? commaHint(word) : ""));
  name = upper(word);
  const std::vector<const KeywordInfo*> infos = findKeywords(name);
  if (infos.empty()) {
    const std::string suggestion = suggestKeyword(name);
    const std::string hint = suggestion.empty() ? "" : "; did you mean " + suggestion + "?";
    if (name.size() > kMaxKeywordLength)
      fail(lineNo, "", "keyword " + show(word) + " is longer than 8 characters" + hint);
    fail(lineNo, "", "unknown keyword " + show(word) + hint);
  }
  return infos.front();
}

// SPACAR reads nothing after the end of the input, but SPACAR Light writes its VISUALIZATION
// section (cross-sections, colours; pictures only) after END END: it is found there too.
void Reader::findVisualizationAfterEnd(size_t pos, int lineNo) {
  while (visualizationAt_ == std::string_view::npos && pos < text_.size()) {
    size_t nl = text_.find('\n', pos);
    if (nl == std::string_view::npos) nl = text_.size();
    std::string_view line = text_.substr(pos, nl - pos);
    pos = nl + 1;
    ++lineNo;
    const size_t b = line.find_first_not_of(" \t\r");
    if (b == std::string_view::npos) continue;
    const size_t e = line.find_first_of(" \t\r", b);
    if (upper(std::string(line.substr(b, e == std::string_view::npos ? line.size() - b : e - b))) == "VISUALIZATION") {
      visualizationAt_ = std::min(pos, text_.size());
      visualizationLine_ = lineNo + 1;
    }
  }
}

void Reader::scan() {
  // Block state: the first block is open from the start; after an END no block is open until the
  // next ordinary keyword opens one.
  bool open = true;
  int closed = 0;          // number of blocks closed by END
  int openedAt = 0;        // line of the first statement of the open block
  bool haltSeen = false;   // END HALT after the first block
  bool afterHalt = false;  // HALT after a later block: a mode-9 transfer block may follow
  bool inTransfer = false;
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

    std::string name;
    const KeywordInfo* info = lineKeyword(tokens, lineNo, name);
    any = true;

    // After END HALT closing a later block: a mode-9 transfer block (INPUTF, OUTX, ...) up to its
    // END is recorded and reported; anything else ends the input there, as before.
    if (afterHalt && !inTransfer && info->action != Action::End) {
      if (!info->transfer) {
        done = true;
        continue;
      }
      inTransfer = true;
      transferFirst_ = lineNo;
    }
    if (inTransfer) {
      if (info->action == Action::End) {
        inTransfer = false;
        afterHalt = false;
        open = false;
        continue;
      }
      if (!info->transfer)
        fail(lineNo, name,
             "only mode-9 transfer keywords (INPUTF, INX, OUTF, OUTX, OUTXP) belong in the "
             "transfer block after END HALT (begun at line " +
                 std::to_string(transferFirst_) + "): missing END?");
      Statement st;
      st.line = lineNo;
      st.keyword = name;
      st.args.assign(tokens.begin() + 1, tokens.end());
      st.info = info;
      checkArgs(st, info->args);
      transfer_.push_back(std::move(st));
      continue;
    }
    if (info->transfer)
      fail(lineNo, name,
           "a mode-9 transfer keyword: it belongs in the transfer block after the dynamic block's END HALT "
           "(kinematic block, END HALT, dynamic block, END HALT, transfer block, END END)");

    if (info->action == Action::Unsupported)
      fail(lineNo, name,
           "SPACAR keyword, not supported by flexmb yet (" + info->meaning + "); " + info->unsupportedNote);

    Statement st;
    st.line = lineNo;
    st.keyword = name;
    st.args.assign(tokens.begin() + 1, tokens.end());

    const auto noArgs = [&] {
      if (!st.args.empty()) fail(lineNo, name, "expected no arguments, found " + std::to_string(st.args.size()));
    };
    const std::string blockName = closed == 0 ? "first block" : "block " + std::to_string(closed + 1);
    switch (info->action) {
      case Action::End:
        noArgs();
        if (!open) {  // an empty block: END END ends the input
          done = true;
        } else {
          open = false;
          endLines_.push_back(lineNo);
          ++closed;
        }
        afterHalt = false;
        continue;
      case Action::Halt:
        noArgs();
        if (open)
          fail(lineNo, name,
               "inside the " + blockName + " (begun at line " + std::to_string(openedAt) + "): missing END");
        if (closed == 1 && !haltSeen) {
          haltSeen = true;  // END HALT after the kinematic block: a separator
        } else {
          afterHalt = true;  // a transfer block may follow; else the input ends here
        }
        continue;
      case Action::Eof:
      case Action::Visualization:
        if (open)
          fail(lineNo, name,
               "inside the " + blockName + " (begun at line " + std::to_string(openedAt) + "): missing END");
        if (info->action == Action::Visualization) {
          visualizationAt_ = std::min(pos, text_.size());
          visualizationLine_ = lineNo + 1;
        }
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
    st.block = closed;
    st.info = info;  // provisional (dialect detection); resolve() picks the block's entry
    statements_.push_back(std::move(st));
  }
  findVisualizationAfterEnd(pos, lineNo);
  if (!any) {
    if (lastLine_ == 0) fail(0, "", "the file is empty");
    fail(0, "", "the file holds no statements (only comments or blank lines)");
  }
  if (inTransfer)
    fail(lastLine_, "",
         "end of file inside the transfer block (begun at line " + std::to_string(transferFirst_) + "): missing END");
  if (open && !done)
    fail(lastLine_, "",
         std::string("end of file inside the ") + (closed == 0 ? "kinematic block" : "dynamic block") +
             " (begun at line " + std::to_string(openedAt) + "): missing END");
}

// The table entry a statement means in its block, once the dialect is known.
//   SPACAR 2013+: the first block is the kinematic block, every later one a dynamic/static block.
//   SPACAR95: the first block may hold every keyword (the manual's example is one block); a later
//   block holds dynamic keywords and restated roles (FIX, INPUTX, DYNE, ... without values);
//   elements and coordinates belong to the first block.
void Reader::resolve(Statement& s, bool spacar95) const {
  const int kinEnd = endLines_.empty() ? 0 : endLines_.front();
  if (s.block == 0) {
    s.info = findKeyword(s.keyword, BlockKind::Kinematic);
    if (!s.info && spacar95) s.info = findKeyword(s.keyword, BlockKind::Dynamic);
    if (!s.info)
      fail(s.line, s.keyword,
           "belongs to a dynamic/static block, after the kinematic block's END (is the "
           "END missing?)");
    return;
  }
  if (spacar95) {
    const KeywordInfo* kin = findKeyword(s.keyword, BlockKind::Kinematic);
    if (kin) {
      switch (kin->action) {
        case Action::Fix:
        case Action::InputXRole:
        case Action::DynX:
        case Action::DynE:
        case Action::Rlse:
        case Action::InputERole:
          s.info = kin;
          return;  // a role restated in a later block
        default:
          break;
      }
    }
    s.info = findKeyword(s.keyword, BlockKind::Dynamic);
    if (!s.info)
      fail(s.line, s.keyword,
           "belongs to the first block (elements and coordinates cannot change after "
           "the first END, at line " +
               std::to_string(kinEnd) + ")");
    return;
  }
  s.info = findKeyword(s.keyword, BlockKind::Dynamic);
  if (!s.info)
    fail(s.line, s.keyword, "belongs to the kinematic block, which ended with END at line " + std::to_string(kinEnd));
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
             ") is SPACAR95 only, " + s13->keyword + " (line " + std::to_string(s13->line) + ") is SPACAR 2013+ only");
  }
  return s95 ? core::Dialect::Spacar95 : core::Dialect::Spacar2013;
}

std::optional<std::string> Reader::layoutError(const Statement& s, const std::vector<ArgSpec>& layout) const {
  const int n = static_cast<int>(s.args.size());
  const int lo = KeywordInfo::minArgs(layout), hi = KeywordInfo::maxArgs(layout);
  if (n < lo || (hi >= 0 && n > hi)) {
    std::string hint;
    for (const Token& t : s.args)
      if (!t.quoted && t.text.find(',') != std::string::npos) {
        hint = "; " + show(t.text) + " holds a comma" + commaHint(t.text);
        break;
      }
    return KeywordInfo::expectation(layout) + ", found " + std::to_string(n) + hint;
  }
  for (size_t k = 0; k < s.args.size(); ++k) {
    const ArgSpec& spec = k < layout.size() ? layout[k] : layout.back();
    const Token& t = s.args[k];
    switch (spec.type) {
      case ArgType::Node:
      case ArgType::Element:
      case ArgType::Component:
      case ArgType::Count:
      case ArgType::Integer: {
        if (t.quoted) return "expected an integer for " + spec.name + ", found " + showToken(t);
        long long v = 0;
        const NumParse p = parseWhole(t.text, v);
        if (p == NumParse::OutOfRange) return "integer out of range for " + spec.name + ": " + show(t.text);
        if (p != NumParse::Ok)
          return "expected an integer for " + spec.name + ", found " + show(t.text) + commaHint(t.text);
        if (spec.type == ArgType::Integer ? v < 0 : v <= 0)
          return std::string("expected a ") + (spec.type == ArgType::Integer ? "non-negative" : "positive") +
                 " integer for " + spec.name + ", found " + show(t.text);
        break;
      }
      case ArgType::Real: {
        if (t.quoted) return "expected a number for " + spec.name + ", found " + showToken(t);
        double v = 0.0;
        const NumParse p = parseReal(t.text, v);
        if (p == NumParse::OutOfRange) return "number out of range for " + spec.name + ": " + show(t.text);
        if (p != NumParse::Ok)
          return "expected a number for " + spec.name + ", found " + show(t.text) + commaHint(t.text);
        break;
      }
      case ArgType::Word:
        break;
      case ArgType::Name: {
        bool ok = !t.quoted && !t.text.empty() && std::isalpha(static_cast<unsigned char>(t.text[0]));
        for (char c : t.text) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
        if (!ok) return "expected a MATLAB function name for " + spec.name + ", found " + showToken(t);
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
  if (k >= s.args.size() || parseWhole(s.args[k].text, v) != NumParse::Ok)
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

// EM, ESTIFF, EDAMP or ESIG with the element number alone: oopspa's writer gives every element
// such a line, also those without the property, and SPACAR runs those files. Nothing is set
// (ModelBuilder::noValues: a note naming the lines; the element must exist). Anything else that
// is short falls through to the layout's error. EMASS and EDAMPP (SPACAR95) stay strict.
// True when s was such a line.
bool propertyWithoutValues(const Statement& s, core::ModelBuilder& b) {
  const KeywordInfo& info = *s.info;
  if (s.args.size() == 1 && !s.args[0].quoted &&
      (info.name == "EM" || info.name == "ESTIFF" || info.name == "EDAMP" || info.name == "ESIG")) {
    long long element = 0;
    if (parseWhole(s.args[0].text, element) == NumParse::Ok && element > 0) {
      b.noValues(info.name, static_cast<int>(element), s.line);
      return true;
    }
  }
  return false;
}

void Reader::checkLayout(const Statement& s, bool spacar95) const {
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
}

bool Reader::applySetting(const Statement& s, core::ModelBuilder& b, bool spacar95) {
  const int line = s.line;
  auto positive = [&](double v, const std::string& what) {
    if (!(v > 0.0)) {
      std::ostringstream o;
      o << what << " must be positive, found " << v;
      fail(line, s.keyword, o.str());
    }
    return v;
  };
  core::AnalysisSettings& set = b.settings();
  switch (s.info->action) {
    case Action::OutLevel:
      set.outputLevel = integer(s, 0);
      if (s.args.size() > 1) set.transferFunctionLevel = integer(s, 1);
      break;
    case Action::Ignored:
      b.addNote(s.keyword + " (line " + std::to_string(line) +
                "): SPACAR95 run setting, accepted and ignored by flexmb");
      break;
    case Action::TimeStep:
      if (spacar95) {  // a period from the current time; the end time is fixed at the block's END
        set.outputIntervals = integer(s, 0);
        period_ = positive(real(s, 1), "the TIMESTEP period");
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
    case Action::HMax:
      set.hmax = positive(real(s, 0), "the maximum step size");
      break;
    case Action::EpsKin:
      set.kinematicTol = positive(real(s, 0), "the kinematic tolerance");
      set.kinematicTolGiven = true;
      break;
    case Action::MaxIterat:
      set.maxIterations = integer(s, 0);
      break;
    case Action::IterStep:
      set.maxIterations = integer(s, 0);
      set.loadSteps = integer(s, 1);
      if (auto tol = optReal(s, 2)) {
        set.kinematicTol = positive(*tol, "the tolerance");
        set.kinematicTolGiven = true;
      }
      // Fields 4 and 5 (control fields) are read and not used; field 6: initial-load steps.
      set.initialLoadSteps = s.args.size() > 5 ? integer(s, 5) : 0;
      break;
    case Action::Time:
      set.t0 = real(s, 0);
      timeLine_ = line;
      break;
    case Action::UserStress:
      userStress_ = s.args[0].text, userStressLine_ = line;
      break;
    case Action::UserInput:
      userInput_ = s.args[0].text, userInputLine_ = line;
      break;
    default:
      return false;
  }
  return true;
}

void Reader::apply(const Statement& s, core::ModelBuilder& b, bool spacar95) {
  const KeywordInfo& info = *s.info;
  if (propertyWithoutValues(s, b)) return;
  checkLayout(s, spacar95);
  if (applySetting(s, b, spacar95)) return;
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
  using core::Role;
  switch (info.action) {
    case Action::Element: {
      const size_t nn = info.elementType->slots.size();
      std::vector<int> nodes;
      for (size_t k = 1; k <= nn && k < s.args.size(); ++k) nodes.push_back(integer(s, k));
      if (info.elementType->vector.empty())
        b.addElement(*info.elementType, integer(s, 0), nodes, line);
      else
        b.addElement(*info.elementType, integer(s, 0), nodes, reals(1 + nn), line);
      break;
    }
    case Action::Coordinates:
    case Action::CoordinatesXY:
    case Action::CoordinatesBeta:
      b.setCoordinates(integer(s, 0), reals(1), line);
      break;
    case Action::ReferenceCoordinates:
      b.setReferenceCoordinates(integer(s, 0), reals(1), line);
      break;
    case Action::Fix:
      b.setCoordinateRole(integer(s, 0), ints(1), Role::Fixed, line);
      break;
    case Action::InputXRole:
      b.setCoordinateRole(integer(s, 0), ints(1), Role::Input, line);
      break;
    case Action::DynX:
      b.setCoordinateRole(integer(s, 0), ints(1), Role::Dynamic, line);
      break;
    case Action::DynE:
      b.setDeformationRole(integer(s, 0), ints(1), Role::Dynamic, line);
      break;
    case Action::Rlse:
      b.setDeformationRole(integer(s, 0), ints(1), Role::Calculable, line);
      break;
    case Action::InputERole:
      b.setDeformationRole(integer(s, 0), ints(1), Role::Input, line);
      break;
    case Action::LumpedMass:
      if (s.args.size() > 2)
        b.setNodeInertia(integer(s, 0), reals(1), line);  // spatial tensor
      else
        b.setLumpedMass(integer(s, 0), real(s, 1), line);
      break;
    case Action::ElementInertia:
      b.setElementInertia(integer(s, 0), reals(1), line);  // layout by element type
      break;
    case Action::Stiffness:
      b.setStiffness(integer(s, 0), reals(1), line);
      break;
    case Action::Damping:
      b.setDamping(integer(s, 0), reals(1), line);
      break;
    case Action::Force:
      b.addForce(integer(s, 0), reals(1), line);
      break;
    case Action::ForceIncrement:
      b.addForceIncrement(integer(s, 0), reals(1), line);
      break;
    case Action::Gravity:
      b.setGravity(real(s, 0), real(s, 1), optReal(s, 2).value_or(0.0), line);
      break;
    case Action::InputXValues:
      b.setInputCoordinate(integer(s, 0), integer(s, 1), real(s, 2), optReal(s, 3), optReal(s, 4), line);
      break;
    case Action::InputEValues:
      b.setInputDeformation(integer(s, 0), integer(s, 1), real(s, 2), optReal(s, 3), optReal(s, 4), line);
      break;
    case Action::XD:
      b.setCoordinateRate(integer(s, 0), integer(s, 1), real(s, 2), line);
      break;
    case Action::XDD:
      b.setCoordinateAcceleration(integer(s, 0), integer(s, 1), real(s, 2), line);
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
    case Action::InputIncrement:
      b.setInputIncrement(integer(s, 0), integer(s, 1), real(s, 2), line);
      break;
    case Action::Prestress:  // ESIG e s1 [s2 ... sn]: a value per deformation (ModelBuilder::setPrestress)
      b.setPrestress(integer(s, 0), reals(1), line);
      break;
    case Action::Length0:
      b.setReferenceLength(integer(s, 0), real(s, 1), line);
      break;
    case Action::TimeForce:
      b.addTimeForce(integer(s, 0), integer(s, 1), function(s, 2, "f(t)"), line);
      break;
    case Action::TimeStress:
      b.addTimeStress(integer(s, 0), integer(s, 1), function(s, 2, "sigma(t)"), line);
      break;
    case Action::Reference:
      b.setReference(integer(s, 0), integer(s, 1), function(s, 2, "eref(t)"), line);
      break;
    case Action::InputXFunctions:
      b.setInputCoordinateFunctions(integer(s, 0), integer(s, 1), function(s, 2, "x(t)"), function(s, 3, "v(t)"),
                                    function(s, 4, "a(t)"), line);
      break;
    case Action::InputEFunctions:
      b.setInputDeformationFunctions(integer(s, 0), integer(s, 1), function(s, 2, "e(t)"), function(s, 3, "v(t)"),
                                     function(s, 4, "a(t)"), line);
      break;
    case Action::OutLevel:  // run settings: applySetting
    case Action::Ignored:
    case Action::TimeStep:
    case Action::EpsInt:
    case Action::ErrorTol:
    case Action::HMax:
    case Action::EpsKin:
    case Action::MaxIterat:
    case Action::IterStep:
    case Action::Time:
    case Action::UserStress:
    case Action::UserInput:
    case Action::End:
    case Action::Halt:
    case Action::Eof:
    case Action::Visualization:
    case Action::Transfer:
    case Action::Unsupported:
      fail(line, s.keyword, "internal: unexpected statement");
      break;
  }
}

std::vector<AnalysisStage> Reader::build(const ReadOptions& options) {
  scan();
  const core::Dialect dialect = options.dialect ? *options.dialect : detect();
  const bool spacar95 = dialect == core::Dialect::Spacar95;
  for (Statement& st : statements_) resolve(st, spacar95);
  core::ModelBuilder b(file_);
  b.setDialect(dialect);
  std::map<int, std::string> keywordAt;
  bool anyElement = false;
  const int kinematicLast = endLines_.empty() ? 0 : endLines_.front();
  const Statement* current = nullptr;
  core::ElementOptions eo;
  eo.elongation = options.elongation ? *options.elongation : defaultElongation(dialect);
  std::vector<AnalysisStage> stages;
  bool ran = false;  // an earlier block ran an analysis: the state continues from it
  try {
    size_t k = 0;
    const int nBlocks = static_cast<int>(endLines_.size());
    for (int block = 0; block < nBlocks; ++block) {
      const size_t first = k;
      for (; k < statements_.size() && statements_[k].block == block; ++k) {
        const Statement& s = statements_[k];
        current = &s;
        keywordAt[s.line] = s.keyword;
        if (s.info->action == Action::Element) anyElement = true;
        if (ran) {
          switch (s.info->action) {
            case Action::E:
            case Action::ED:
            case Action::EDD:
            case Action::StartDE:
              fail(s.line, s.keyword,
                   "initial values belong in the first analysis: after the analysis of "
                   "an earlier block the state continues from where it ended");
            default:
              break;
          }
        }
        apply(s, b, spacar95);
      }
      current = nullptr;
      if (k == first) continue;  // an empty block (END END)
      core::AnalysisSettings& set = b.settings();
      if (spacar95 && period_) set.tEnd = set.t0 + *period_;
      if (set.timestepGiven && !(set.tEnd > set.t0)) {
        std::ostringstream o;
        o << "the end time " << set.tEnd << " must be larger than the start time " << set.t0;
        fail(timestepLine_, "TIMESTEP", o.str());
      }
      const bool runs = set.timestepGiven;
      if (!runs) set.tEnd = std::max(set.tEnd, set.t0 + 1.0);  // the default period, as before
      if (!anyElement)
        fail(kinematicLast, kinematicLast ? "END" : "",
             "the model defines no elements (the kinematic block needs at least one)");
      AnalysisStage stage;
      stage.model = b.finalize(eo);
      stage.model.userStressFunction = userStress_, stage.model.userStressLine = userStressLine_;
      stage.model.userInputFunction = userInput_, stage.model.userInputLine = userInputLine_;
      stage.runs = runs;
      stage.endLine = endLines_[block];
      // The next block continues from the end of this one: the current time advances, and the
      // inputs given by value and rate restart from their values there (x + v (t - TIME) + ...),
      // so that a later XD or XDD changes the motion from the current time on.
      if (runs) {
        ran = true;
        const double t1 = set.tEnd;
        const core::Model& m = stage.model;
        for (const auto& r : m.inputX) {
          if (r.fx) continue;
          double x, v, a;
          r.evaluate(t1, x, v, a);
          const core::Node& n = m.nodes[m.xOwnerNode[r.index]];
          b.setInputCoordinate(n.label, r.index - n.firstCoord + 1, x, v, a, stage.endLine);
          b.setCoordinateRate(n.label, r.index - n.firstCoord + 1, v, stage.endLine);  // after earlier XD
        }
        for (const auto& r : m.inputE) {
          if (r.fx) continue;
          double x, v, a;
          r.evaluate(t1, x, v, a);
          const int ei = m.eOwnerElement[r.index];
          b.setInputDeformation(m.elements[ei].label, r.index - m.elements[ei].firstDef + 1, x, v, a, stage.endLine);
        }
        set.t0 = t1;
        set.timestepGiven = false;
        period_.reset();
      }
      stages.push_back(std::move(stage));
    }
    if (stages.empty())
      fail(kinematicLast, kinematicLast ? "END" : "",
           "the model defines no elements (the kinematic block needs at least one)");
    resolveTransfer(stages.back().model);
    if (visualizationAt_ != std::string_view::npos) {
      VisualizationSection vis = parseVisualization(text_.substr(visualizationAt_), visualizationLine_, file_);
      for (auto& stage : stages) {
        core::Model& m = stage.model;
        for (const auto& [label, look] : vis.appearance)
          if (m.elementByLabel.count(label)) m.appearance[label] = look;
        for (const auto& note : vis.notes) m.notes.push_back(note);
      }
      std::string unknown;
      for (const auto& [label, look] : vis.appearance)
        if (!stages.back().model.elementByLabel.count(label))
          (unknown += unknown.empty() ? "" : ", ") += std::to_string(label);
      if (!unknown.empty())
        for (auto& stage : stages)
          stage.model.notes.push_back(file_ + ": VISUALIZATION names elements the model does not have: " + unknown +
                                      " (ignored)");
    }
    return stages;
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

void Reader::resolveTransfer(core::Model& model) const {
  using Kind = core::TransferChannel::Kind;
  for (const Statement& s : transfer_) {
    core::TransferChannel c;
    c.keyword = s.keyword;
    c.line = s.line;
    c.number = integer(s, 0);
    const int label = integer(s, 1);
    c.component = integer(s, 2);
    c.kind = s.keyword == "INPUTF"  ? Kind::Force
             : s.keyword == "INX"   ? Kind::Motion
             : s.keyword == "OUTX"  ? Kind::Coordinate
             : s.keyword == "OUTXP" ? Kind::Velocity
                                    : Kind::NodalForce;
    const auto it = model.nodeByLabel.find(label);
    if (it == model.nodeByLabel.end())
      fail(s.line, s.keyword, "node " + std::to_string(label) + " does not exist (no element of the model uses it)");
    c.node = it->second;
    const core::Node& n = model.nodes[c.node];
    const std::string where = "coordinate " + std::to_string(c.component) + " of node " + std::to_string(label);
    c.axis = n.kind == core::NodeKind::EulerParameters;
    const int ncomp = c.axis ? 3 : n.dim();
    if (c.component > ncomp)
      fail(s.line, s.keyword,
           "node " + std::to_string(label) + " has " + std::to_string(ncomp) + " component" + (ncomp > 1 ? "s" : "") +
               (c.axis ? " (global axes 1, 2, 3 of its rotation)" : "") + ", not " + std::to_string(c.component));
    c.coord = n.firstCoord + (c.axis ? 0 : c.component - 1);
    // Roles of the coordinate (a spatial orientation node: its Euler parameters).
    int fixed = 0, input = 0, free = 0;
    for (int k = c.axis ? 0 : c.component - 1; k < (c.axis ? 4 : c.component); ++k) {
      const core::Role r = model.xRole[n.firstCoord + k];
      (r == core::Role::Fixed ? fixed : r == core::Role::Input ? input : free) += 1;
    }
    const std::string role = fixed ? "fixed" : input ? "an input coordinate (INPUTX)" : "free";
    switch (c.kind) {
      case Kind::Force:
        if (free == 0)
          fail(s.line, s.keyword,
               where + " is " + role + ": not a load point (" +
                   (fixed ? "a force there goes into the support" : "its prescribed motion takes any force there") +
                   "); INPUTF needs a calculable or DYNX coordinate");
        break;
      case Kind::Motion:
        if (c.axis || input == 0)
          fail(s.line, s.keyword,
               where + (c.axis ? " is an Euler-parameter rotation" : " is " + role) +
                   ": INX needs a position coordinate or planar angle that is an input coordinate (INPUTX in the "
                   "kinematic block), whose motion is the input");
        break;
      case Kind::Coordinate:
      case Kind::Velocity:
        if (free == 0 && input == 0)
          fail(s.line, s.keyword, where + " is fixed: it does not move, so it has no transfer function");
        break;
      case Kind::NodalForce:
        if (fixed == 0 && input == 0)
          fail(s.line, s.keyword,
               where +
                   " is free: the force there is the applied load; OUTF takes a fixed or input coordinate "
                   "(the force the support or the prescribed motion takes)");
        break;
    }
    (c.kind == Kind::Force || c.kind == Kind::Motion ? model.transferInputs : model.transferOutputs).push_back(c);
  }
  // Channel numbers: 1, 2, ... without gaps or repeats, separately for the inputs and the outputs.
  for (auto* list : {&model.transferInputs, &model.transferOutputs}) {
    const char* what = list == &model.transferInputs ? "input" : "output";
    std::sort(list->begin(), list->end(), [](const auto& a, const auto& b) {
      return a.number != b.number ? a.number < b.number : a.line < b.line;
    });
    for (std::size_t k = 0; k < list->size(); ++k) {
      const auto& c = (*list)[k];
      if (k > 0 && (*list)[k - 1].number == c.number)
        fail(c.line, c.keyword,
             std::string(what) + " " + std::to_string(c.number) + " is given twice (also at line " +
                 std::to_string((*list)[k - 1].line) + ")");
      if (c.number != static_cast<int>(k) + 1)
        fail(c.line, c.keyword,
             std::string(what) + " numbers must run 1, 2, ... without gaps: " + what + " " + std::to_string(k + 1) +
                 " is missing before " + std::to_string(c.number));
    }
  }
}

}  // namespace

std::vector<AnalysisStage> readDatStagesString(std::string_view text, const std::string& virtualFileName,
                                               const ReadOptions& options) {
  Reader r(text, virtualFileName);
  std::vector<AnalysisStage> stages = r.build(options);
  refineStages(stages, options);
  return stages;
}

core::Model readDatString(std::string_view text, const std::string& virtualFileName, const ReadOptions& options) {
  std::vector<AnalysisStage> stages = readDatStagesString(text, virtualFileName, options);
  return std::move(stages.back().model);
}

core::Dialect detectDialect(std::string_view text, const std::string& virtualFileName) {
  Reader r(text, virtualFileName);
  r.scan();
  return r.detect();
}

std::string readDatText(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw DatError(path, 0, "", "cannot read '" + path + "': it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw DatError(path, 0, "", "cannot open '" + path + "': no such file or not readable");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw DatError(path, 0, "", "cannot read '" + path + "'");
  return ss.str();
}

std::vector<AnalysisStage> readDatStages(const std::string& path, const ReadOptions& options) {
  return readDatStagesString(readDatText(path), path, options);
}

core::Model readDatFile(const std::string& path, const ReadOptions& options) {
  return readDatString(readDatText(path), path, options);
}

}  // namespace flexmb::io
