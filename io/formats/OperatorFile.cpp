#include "io/formats/OperatorFile.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <type_traits>

#include "text/NumberText.hpp"

namespace flexmb::io {
namespace {

constexpr std::string_view kOperatorMagic = "# flexmb reduced operators";

template <class M>
void appendBlock(std::string& out, const char* kind, const char* name, const M& A) {
  out.append(kind).append(" ").append(name).append(" ").append(std::to_string(A.rows())).append(" ");
  out.append(std::to_string(A.cols())).append("\n");
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    for (Eigen::Index j = 0; j < A.cols(); ++j) {
      if (j) out += ',';
      if constexpr (std::is_same_v<typename M::Scalar, int>)
        out += std::to_string(A(i, j));
      else
        text::appendG17(out, A(i, j));
    }
    out += '\n';
  }
}

std::string quotedField(std::string_view f) {
  std::string q = "'";
  q.append(f.substr(0, 40));
  q.append("'");
  return q;
}

class OperatorParser {
 public:
  OperatorParser(const std::string& text, const std::string& name) : in_(text), name_(name) {}
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error(name_ + ":" + std::to_string(line_) + ": " + why);
  }
  bool next(std::string& s) {
    if (!std::getline(in_, s)) return false;
    ++line_;
    if (!s.empty() && s.back() == '\r') s.pop_back();
    return true;
  }
  double number(std::string_view f) const {
    while (!f.empty() && f.front() == ' ') f.remove_prefix(1);
    while (!f.empty() && f.back() == ' ') f.remove_suffix(1);
    double v = 0.0;
    const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
    if (f.empty() || r.ec != std::errc() || r.ptr != f.data() + f.size() || !std::isfinite(v))
      fail(quotedField(f) + " is not a finite number");
    return v;
  }
  // `rows` lines of `cols` comma-separated numbers.
  Eigen::MatrixXd block(long rows, long cols) {
    if (rows < 0 || cols < 0 || rows > 10000000 / std::max(1L, cols)) fail("block size out of range");
    Eigen::MatrixXd A(rows, cols);
    std::string s;
    for (long i = 0; i < rows; ++i) {
      if (!next(s)) fail("the block ends after " + std::to_string(i) + " of its " + std::to_string(rows) + " rows");
      std::string_view rest(s);
      for (long j = 0; j < cols; ++j) {
        const size_t comma = rest.find(',');
        if ((comma == std::string_view::npos) != (j + 1 == cols))
          fail("row with other than " + std::to_string(cols) + " numbers");
        A(i, j) = number(rest.substr(0, comma));
        if (comma != std::string_view::npos) rest.remove_prefix(comma + 1);
      }
    }
    return A;
  }
  int line() const { return line_; }

 private:
  std::istringstream in_;
  std::string name_;
  int line_ = 0;
};

}  // namespace

std::string formatOperators(const core::ReducedOperators& o) {
  std::string out(kOperatorMagic);
  out += "\n";
  auto key = [&](const char* k, const std::string& v) {
    out.append("# ").append(k).append(": ").append(v).append("\n");
  };
  key("dofs", std::to_string(o.dofs));
  key("basis checksum", text::g17(o.basisChecksum));
  if (!o.modelChecksum.empty()) key("model checksum", o.modelChecksum);
  key("tolerance", text::g17(o.tolerance));
  key("force error", text::g17(o.forceError));
  key("mass error", text::g17(o.massError));
  if (!o.outputs.empty()) key("output error", text::g17(o.outputError));
  key("force scale", text::g17(o.forceScale));
  key("mass scale", text::g17(o.massScale));
  key("damping scale", text::g17(o.dampingScale));
  key("load scale", text::g17(o.loadScale));
  key("training samples", std::to_string(o.trainingSamples));
  key("validation samples", std::to_string(o.validationSamples));
  key("training seconds", text::g17(o.trainingSeconds));
  key("operator seconds", text::g17(o.operatorSeconds));
  key("equation 19 seconds", text::g17(o.equation19Seconds));
  std::string range = o.range;
  for (char& c : range)
    if (c == '\n' || c == '\r') c = ' ';
  key("range", range);
  for (const auto& l : o.loads)
    out.append("load ")
        .append(core::operatorLoadKeyword(l.kind))
        .append(" ")
        .append(std::to_string(l.index))
        .append("\n");
  for (const auto& q : o.outputs)
    out.append("output ")
        .append(core::operatorOutputKeyword(q.kind))
        .append(" ")
        .append(std::to_string(q.index))
        .append("\n");
  appendBlock(out, "matrix", "centre", o.centre);
  appendBlock(out, "matrix", "rotation", o.rotation);
  appendBlock(out, "matrix", "lower", o.lower);
  appendBlock(out, "matrix", "upper", o.upper);
  appendBlock(out, "ints", "exponents", o.exponents);
  appendBlock(out, "matrix", "potential", o.potential);
  appendBlock(out, "matrix", "mass", o.mass);
  appendBlock(out, "matrix", "damping", o.damping);
  appendBlock(out, "matrix", "loadFields", o.loadFields);
  if (!o.outputs.empty()) appendBlock(out, "matrix", "outputFields", o.outputFields);
  if (o.heldOut.size()) appendBlock(out, "matrix", "heldOut", o.heldOut);
  return out;
}

core::ReducedOperators parseOperators(const std::string& text, const std::string& name) {
  OperatorParser p(text, name);
  std::string s;
  if (!p.next(s) || s != kOperatorMagic)
    p.fail("not a flexmb operator file (the first line must be '" + std::string(kOperatorMagic) + "')");
  core::ReducedOperators o;
  std::map<std::string, Eigen::MatrixXd> blocks;
  Eigen::MatrixXd exponents;
  while (p.next(s)) {
    if (s.empty()) continue;
    if (s.rfind("# ", 0) == 0) {
      const size_t colon = s.find(": ");
      if (colon == std::string::npos) p.fail("header line without 'key: value'");
      const std::string k = s.substr(2, colon - 2), v = s.substr(colon + 2);
      if (k == "range") {
        o.range = v;
        continue;
      }
      if (k == "model checksum") {
        if (v.size() != 16 || v.find_first_not_of("0123456789abcdef") != std::string::npos)
          p.fail("the model checksum must be 16 hex digits");
        o.modelChecksum = v;
        continue;
      }
      const double x = p.number(v);
      if (k == "dofs")
        o.dofs = static_cast<int>(x);
      else if (k == "basis checksum")
        o.basisChecksum = x;
      else if (k == "tolerance")
        o.tolerance = x;
      else if (k == "force error")
        o.forceError = x;
      else if (k == "mass error")
        o.massError = x;
      else if (k == "output error")
        o.outputError = x;
      else if (k == "force scale")
        o.forceScale = x;
      else if (k == "mass scale")
        o.massScale = x;
      else if (k == "damping scale")
        o.dampingScale = x;
      else if (k == "load scale")
        o.loadScale = x;
      else if (k == "training samples")
        o.trainingSamples = static_cast<int>(x);
      else if (k == "validation samples")
        o.validationSamples = static_cast<int>(x);
      else if (k == "training seconds")
        o.trainingSeconds = x;
      else if (k == "operator seconds")
        o.operatorSeconds = x;
      else if (k == "equation 19 seconds")
        o.equation19Seconds = x;
      else
        p.fail("unknown header key '" + k + "'");
      continue;
    }
    std::istringstream w(s);
    std::string kind, what;
    w >> kind >> what;
    if (kind == "load") {
      long index = -1;
      if (!(w >> index) || index < 0) p.fail("load without a non-negative index");
      core::OperatorLoad l;
      l.index = static_cast<int>(index);
      if (what == "XFT")
        l.kind = core::OperatorLoad::Kind::NodalForce;
      else if (what == "ESIGT")
        l.kind = core::OperatorLoad::Kind::Stress;
      else if (what == "EREF")
        l.kind = core::OperatorLoad::Kind::Reference;
      else
        p.fail("unknown load '" + what + "' (XFT, ESIGT or EREF)");
      o.loads.push_back(l);
      continue;
    }
    if (kind == "output") {
      long index = -1;
      if (!(w >> index) || index < 0) p.fail("output without a non-negative index");
      if (what != "x" && what != "e") p.fail("unknown output '" + what + "' (x or e)");
      o.outputs.push_back(
          {what == "e" ? core::OperatorOutput::Kind::Deformation : core::OperatorOutput::Kind::Coordinate,
           static_cast<int>(index)});
      continue;
    }
    long rows = -1, cols = -1;
    if ((kind != "matrix" && kind != "ints") || !(w >> rows >> cols)) p.fail("expected 'matrix NAME ROWS COLS'");
    static const char* known[] = {"centre", "rotation", "lower",      "upper",        "exponents", "potential",
                                  "mass",   "damping",  "loadFields", "outputFields", "heldOut"};
    if (std::find(std::begin(known), std::end(known), what) == std::end(known)) p.fail("unknown block '" + what + "'");
    if (blocks.count(what)) p.fail("block '" + what + "' given twice");
    blocks[what] = p.block(rows, cols);
  }
  for (const char* need : {"centre", "rotation", "lower", "upper", "exponents", "potential", "mass"})
    if (!blocks.count(need)) throw std::runtime_error(name + ": no block '" + need + "'");
  o.centre = blocks["centre"];
  o.rotation = blocks["rotation"];
  o.lower = blocks["lower"];
  o.upper = blocks["upper"];
  o.exponents = blocks["exponents"].cast<int>();
  o.potential = blocks["potential"];
  o.mass = blocks["mass"];
  o.damping = blocks.count("damping") ? blocks["damping"] : Eigen::MatrixXd();
  o.loadFields = blocks.count("loadFields") ? blocks["loadFields"] : Eigen::MatrixXd();
  o.outputFields = blocks.count("outputFields") ? blocks["outputFields"] : Eigen::MatrixXd();
  o.heldOut = blocks.count("heldOut") ? blocks["heldOut"] : Eigen::MatrixXd();
  const long m = o.lower.size(), P = o.exponents.rows();
  auto bad = [&](const std::string& why) { throw std::runtime_error(name + ": " + why); };
  if (m == 0 || o.upper.size() != m || o.centre.size() != m || o.rotation.rows() != m || o.rotation.cols() != m ||
      o.exponents.cols() != m)
    bad("centre, rotation, lower, upper and exponents do not agree on the number of reduced coordinates");
  for (long i = 0; i < m; ++i)
    if (!(o.lower[i] < o.upper[i])) bad("empty range in coordinate " + std::to_string(i + 1));
  if ((o.exponents.array() < 0).any() || (o.exponents.cast<double>() - blocks["exponents"]).cwiseAbs().maxCoeff() > 0)
    bad("exponents must be non-negative integers");
  const long packed = m * (m + 1) / 2;
  if (o.potential.size() > P || o.mass.rows() != packed || o.mass.cols() > P ||
      (o.damping.size() && (o.damping.rows() != packed || o.damping.cols() > P)) || o.loadFields.rows() > P ||
      o.loadFields.cols() != static_cast<long>(o.loads.size()) || o.outputFields.rows() > P ||
      o.outputFields.cols() != static_cast<long>(o.outputs.size()) || (o.heldOut.size() && o.heldOut.cols() != m))
    bad("the coefficient blocks do not fit the terms (exponents), loads and outputs");
  return o;
}

void writeOperators(const std::string& path, const core::ReducedOperators& ops) {
  const std::string text = formatOperators(ops);
  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path);
}

core::ReducedOperators readOperators(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read " + path);
  std::ostringstream s;
  s << f.rdbuf();
  return parseOperators(s.str(), path);
}

std::string operatorPathFor(const std::string& basisPath) {
  return std::filesystem::path(basisPath).replace_extension(".operators").string();
}

}  // namespace flexmb::io
