#include "io/formats/SpacarResults.hpp"

#include "io/formats/OriginalResults.hpp"
#include "io/formats/ResultWriter.hpp"

#include <matio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace flexmb::io {
namespace {

using core::Role;

// Arrays of at least this many bytes are written compressed (smaller ones cost more to compress
// than they save).
constexpr std::size_t kCompressAbove = 32 * 1024;

// Where the variables of one result file go: a MAT v5 file (MatWriter) or memory (MatCollector).
class MatSink {
 public:
  virtual ~MatSink() = default;
  // Column-major data of an r x c (x p) double array; one page (p = 1) is an r x c matrix, which is
  // what Octave and MATLAB make of it anyway.
  virtual void write(const char* name, std::size_t r, std::size_t c, std::vector<double> data, std::size_t p = 1) = 0;
  // A char matrix, one string per row, blank-padded (MATLAB's char(...) of the strings).
  virtual void text(const char* name, const std::vector<std::string>& rows) = 0;
  void scalar(const char* name, double v) { write(name, 1, 1, {v}); }
  void matrix(const char* name, const Eigen::MatrixXd& A) {
    write(name, A.rows(), A.cols(), std::vector<double>(A.data(), A.data() + A.size()));
  }
};

// One MAT v5 file; closed (and checked) by close(), closed silently on an exception.
class MatWriter : public MatSink {
 public:
  explicit MatWriter(std::string path) : path_(std::move(path)) {
    // Probe with stdio first: matio reports failures without a reason.
    errno = 0;
    FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f)
      throw std::runtime_error("cannot open '" + path_ +
                               "' for writing: " + (errno ? std::strerror(errno) : "unknown error"));
    std::fclose(f);
    mat_ = Mat_CreateVer(path_.c_str(), kMatHeader, MAT_FT_MAT5);
    if (!mat_) throw std::runtime_error("cannot write '" + path_ + "': matio could not create the MAT file");
  }
  ~MatWriter() override {
    if (mat_) Mat_Close(mat_);
  }
  MatWriter(const MatWriter&) = delete;
  MatWriter& operator=(const MatWriter&) = delete;

  void write(const char* name, std::size_t r, std::size_t c, std::vector<double> data, std::size_t p = 1) override {
    size_t dims[3] = {r, c, p};
    static double dummy = 0.0;
    double* ptr = data.empty() ? &dummy : data.data();
    matvar_t* v = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, p != 1 ? 3 : 2, dims, ptr, MAT_F_DONT_COPY_DATA);
    if (!v) throw std::runtime_error("cannot write '" + path_ + "': matio could not create variable '" + name + "'");
    // Large arrays zlib-compressed (MAT v5's miCOMPRESSED, which MATLAB's and Octave's load and
    // getfrsbf read as any other): the per-step matrices of a static run are mostly zeros (C0, N0,
    // D0 without damping) and sparse patterns (a 64-element roll-up wrote 290 MB of .sbm uncompressed).
    const bool large = data.size() * sizeof(double) >= kCompressAbove;
    const int rc = Mat_VarWrite(mat_, v, large ? MAT_COMPRESSION_ZLIB : MAT_COMPRESSION_NONE);
    Mat_VarFree(v);
    if (rc != 0)
      throw std::runtime_error("cannot write '" + path_ + "': matio failed to write variable '" + name + "'");
  }
  void text(const char* name, const std::vector<std::string>& rows) override {
    std::size_t w = 0;
    for (const auto& r : rows) w = std::max(w, r.size());
    std::vector<unsigned char> data(rows.size() * w, ' ');
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (std::size_t j = 0; j < rows[i].size(); ++j)
        data[j * rows.size() + i] = static_cast<unsigned char>(rows[i][j]);
    size_t dims[2] = {rows.size(), w};
    static unsigned char dummy = 0;
    matvar_t* v = Mat_VarCreate(name, MAT_C_CHAR, MAT_T_UINT8, 2, dims, data.empty() ? &dummy : data.data(),
                                MAT_F_DONT_COPY_DATA);
    if (!v) throw std::runtime_error("cannot write '" + path_ + "': matio could not create variable '" + name + "'");
    const int rc = Mat_VarWrite(mat_, v, MAT_COMPRESSION_NONE);
    Mat_VarFree(v);
    if (rc != 0)
      throw std::runtime_error("cannot write '" + path_ + "': matio failed to write variable '" + name + "'");
  }
  void close() {
    const int rc = Mat_Close(mat_);
    mat_ = nullptr;
    if (rc != 0) throw std::runtime_error("cannot write '" + path_ + "': matio failed to close it");
  }

 private:
  std::string path_;
  mat_t* mat_ = nullptr;
};

// The variables of one file, kept in memory.
class MatCollector : public MatSink {
 public:
  explicit MatCollector(SpacarFileContents& file) : file_(file) {}
  void write(const char* name, std::size_t r, std::size_t c, std::vector<double> data, std::size_t p = 1) override {
    SpacarVariable v;
    v.name = name;
    v.dims = p != 1 ? std::vector<std::size_t>{r, c, p} : std::vector<std::size_t>{r, c};
    v.data = std::move(data);
    file_.variables.push_back(std::move(v));
  }
  void text(const char* name, const std::vector<std::string>& rows) override {
    SpacarVariable v;
    v.name = name;
    v.isText = true;
    v.text = rows;
    file_.variables.push_back(std::move(v));
  }
  void close() {}

 private:
  SpacarFileContents& file_;
};

int groupOfX(Role r) {
  switch (r) {
    case Role::Fixed:
      return 0;
    case Role::Calculable:
      return 1;
    case Role::Input:
      return 2;
    case Role::Dynamic:
      return 3;
  }
  return 1;
}
// Counting group (nep: fixed, released, input, dynamic; the same order as nxp) and storage rank
// (fixed, input, dynamic, released).
int groupOfE(Role r) { return groupOfX(r); }
constexpr int kERank[4] = {0, 3, 1, 2};

std::string stepText(const SpacarResults& r, std::size_t k) {
  return "step " + std::to_string(k + 1) + " (" + (r.mode == 10 ? "load factor " : "t = ") + std::to_string(r.time[k]) +
         ")";
}

}  // namespace

Eigen::VectorXd SpacarLayout::sortX(const Eigen::VectorXd& v) const {
  Eigen::VectorXd s(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) s[i] = v[xOrder[i]];
  return s;
}
Eigen::VectorXd SpacarLayout::sortE(const Eigen::VectorXd& v) const {
  Eigen::VectorXd s(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) s[i] = v[eOrder[i]];
  return s;
}
Eigen::VectorXd SpacarLayout::unsortX(const Eigen::VectorXd& v) const {
  Eigen::VectorXd s(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) s[xOrder[i]] = v[i];
  return s;
}

SpacarLayout spacarLayout(const core::Model& model) {
  SpacarLayout L;
  std::vector<std::vector<int>> xg(4), eg(4);
  std::vector<char> dynX(model.nx, 0), dynE(model.ne, 0);
  // Dynamic groups in the order of q (the rows of M0).
  for (const auto& d : model.dofs) {
    if (d.isDeformation) {
      eg[kERank[3]].push_back(d.index);
      dynE[d.index] = 1;
    } else {
      xg[3].push_back(d.index);
      dynX[d.index] = 1;
    }
  }
  for (int i = 0; i < model.nx; ++i) {
    const int g = groupOfX(model.xRole[i]);
    ++L.nxp[g];
    if (!dynX[i]) xg[g == 3 ? 1 : g].push_back(i);  // a dynamic role outside q cannot occur; keep it calculable
  }
  for (int j = 0; j < model.ne; ++j) {
    const int g = groupOfE(model.eRole[j]);
    ++L.nep[g];
    if (!dynE[j]) eg[kERank[g == 3 ? 1 : g]].push_back(j);
  }
  // Counts from the groups actually stored (a role without a q entry is counted where it is kept).
  for (int g = 0; g < 4; ++g) L.nxp[g] = static_cast<int>(xg[g].size());
  L.nep[0] = static_cast<int>(eg[0].size());
  L.nep[2] = static_cast<int>(eg[1].size());
  L.nep[3] = static_cast<int>(eg[2].size());
  L.nep[1] = static_cast<int>(eg[3].size());
  for (const auto& g : xg) L.xOrder.insert(L.xOrder.end(), g.begin(), g.end());
  for (const auto& g : eg) L.eOrder.insert(L.eOrder.end(), g.begin(), g.end());
  L.xPos.assign(model.nx, 0);
  L.ePos.assign(model.ne, 0);
  for (int i = 0; i < model.nx; ++i) L.xPos[L.xOrder[i]] = i;
  for (int j = 0; j < model.ne; ++j) L.ePos[L.eOrder[j]] = j;
  for (int i : xg[2]) L.dofColumns.push_back({false, i});
  for (int i : xg[3]) L.dofColumns.push_back({false, i});
  for (int j : eg[1]) L.dofColumns.push_back({true, j});
  for (int j : eg[2]) L.dofColumns.push_back({true, j});
  return L;
}

int elementTypeId(const core::ElementTypeInfo* type) { return type ? type->spacarTypeId : 0; }

SpacarTopology spacarTopology(const core::Model& model, const SpacarLayout& L) {
  int maxNode = 0, width = 0, maxEl = 0, nodesPerEl = 0, defsPerEl = 0;
  for (const auto& n : model.nodes) maxNode = std::max(maxNode, n.label), width = std::max(width, n.dim());
  // Spatial models: 4 columns, as SPACAR's (FIS's USERSIG reads x(lnp(n, :)) as an orientation
  // node's 4 Euler parameters); a node with fewer coordinates has zeros after them.
  if (model.spatial) width = std::max(width, 4);
  for (const auto& E : model.elements) {
    maxEl = std::max(maxEl, E.label);
    nodesPerEl = std::max(nodesPerEl, static_cast<int>(E.nodes.size()));
    defsPerEl = std::max(defsPerEl, E.impl ? E.impl->numDeformations() : 0);
  }
  Eigen::MatrixXd lnp = Eigen::MatrixXd::Zero(maxNode, width);
  for (const auto& n : model.nodes)
    for (int k = 0; k < n.dim(); ++k) lnp(n.label - 1, k) = L.xPos[n.firstCoord + k] + 1;
  Eigen::MatrixXd ln = Eigen::MatrixXd::Zero(maxEl, nodesPerEl), le = Eigen::MatrixXd::Zero(maxEl, defsPerEl);
  // it is a row (1 x elements), as IT in SPACAR's own .sbd; rl0 a column, as its RL0.
  Eigen::MatrixXd it = Eigen::MatrixXd::Zero(1, maxEl), rl0 = Eigen::MatrixXd::Zero(maxEl, 1);
  for (const auto& E : model.elements) {
    for (std::size_t j = 0; j < E.nodes.size(); ++j) ln(E.label - 1, j) = model.nodes[E.nodes[j]].label;
    const int nd = E.impl ? E.impl->numDeformations() : 0;
    for (int j = 0; j < nd; ++j) le(E.label - 1, j) = L.ePos[E.firstDef + j] + 1;
    it(0, E.label - 1) = elementTypeId(E.type);
    // Reference length: distance of the first two position nodes in the initial configuration.
    std::vector<const core::Node*> pos;
    for (int ni : E.nodes)
      if (model.nodes[ni].kind == core::NodeKind::Position || model.nodes[ni].kind == core::NodeKind::SpatialPosition)
        pos.push_back(&model.nodes[ni]);
    if (pos.size() >= 2) {
      double s2 = 0.0;
      for (int k = 0; k < std::min(pos[0]->dim(), pos[1]->dim()); ++k) {
        const double d = model.x0[pos[1]->firstCoord + k] - model.x0[pos[0]->firstCoord + k];
        s2 += d * d;
      }
      rl0(E.label - 1, 0) = std::sqrt(s2);
    }
  }
  return {lnp, ln, le, it, rl0};
}

Eigen::MatrixXd spacarElementConstants(const core::Model& model, ElementConstant which, Eigen::Index rows,
                                       Eigen::Index minCols) {
  auto values = [which](const core::ElementEntry& el) -> const std::vector<double>& {
    switch (which) {
      case ElementConstant::Stiffness:
        return el.stiffnessParams;
      case ElementConstant::Damping:
        return el.dampingParams;
      case ElementConstant::Mass:
        break;
    }
    return el.inertiaParams;
  };
  Eigen::Index cols = minCols;
  for (const auto& el : model.elements) cols = std::max<Eigen::Index>(cols, values(el).size());
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(rows, cols);
  for (const auto& el : model.elements) {
    if (el.label < 1 || el.label > rows) continue;
    const auto& v = values(el);
    for (std::size_t k = 0; k < v.size(); ++k) C(el.label - 1, static_cast<Eigen::Index>(k)) = v[k];
  }
  return C;
}

Eigen::MatrixXd spacarElementTriads(const core::Model& model, Eigen::Index rows, int end) {
  if (!model.spatial) return Eigen::MatrixXd(0, 0);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(rows, 9);
  Eigen::Matrix3d A;
  for (const auto& el : model.elements) {
    if (!el.impl || el.label < 1 || el.label > rows || !el.impl->elementFrame(end, A)) continue;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) R(el.label - 1, 3 * c + r) = A(r, c);
  }
  return R;
}

Eigen::MatrixXd spacarElementPrestress(const core::Model& model, Eigen::Index rows) {
  if (model.sigma0.size() != model.ne) return Eigen::MatrixXd(0, 0);
  if (model.sigma0.isZero(0.0)) return Eigen::MatrixXd(0, 0);
  Eigen::Index cols = 0;
  for (const auto& el : model.elements)
    if (el.impl) cols = std::max<Eigen::Index>(cols, el.impl->numDeformations());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(rows, cols);
  for (const auto& el : model.elements)
    if (el.impl && el.label >= 1 && el.label <= rows)
      for (int i = 0; i < el.impl->numDeformations(); ++i) S(el.label - 1, i) = model.sigma0[el.firstDef + i];
  return S;
}

namespace {

// What the results hold (checked: sizes and finite values; std::invalid_argument naming the first
// that is not as it should be).
struct SpacarContents {
  bool hasDx = false, hasDe = false, hasD = false, hasFx = true, hasSys = false, hasK0B = false;
  std::size_t m = 0, nev = 0;
};
SpacarContents checkSpacarResults(const std::string& base, const core::Model& model, const SpacarResults& r,
                                  const SpacarLayout& L) {
  const std::size_t nt = r.time.size(), nx = model.nx, ne = model.ne;
  SpacarContents c;
  bool &hasDx = c.hasDx, &hasDe = c.hasDe, &hasD = c.hasD, &hasFx = c.hasFx, &hasSys = c.hasSys, &hasK0B = c.hasK0B;
  std::size_t &m = c.m, &nev = c.nev;
  hasDx = hasDe = hasD = nt > 0;
  for (std::size_t k = 0; k < nt; ++k) {
    const SpacarStep& s = r.steps[k];
    auto check = [&](const char* name, const Eigen::MatrixXd& v, std::size_t rows, std::size_t cols) {
      if (static_cast<std::size_t>(v.rows()) != rows || static_cast<std::size_t>(v.cols()) != cols)
        throw std::invalid_argument("SPACAR results '" + base + "': " + name + " at " + stepText(r, k) + " is " +
                                    std::to_string(v.rows()) + " x " + std::to_string(v.cols()) + ", expected " +
                                    std::to_string(rows) + " x " + std::to_string(cols));
      if (!v.allFinite())
        throw std::invalid_argument("SPACAR results '" + base + "': non-finite " + name + " at " + stepText(r, k));
    };
    check("x", s.x, nx, 1), check("xd", s.xd, nx, 1), check("xdd", s.xdd, nx, 1), check("fxt", s.fxt, nx, 1);
    hasFx = hasFx && s.fx.size() > 0 && s.fxgrav.size() > 0;
    if (s.fx.size()) check("fx", s.fx, nx, 1);
    if (s.fxgrav.size()) check("fxgrav", s.fxgrav, nx, 1);
    check("e", s.e, ne, 1), check("ed", s.ed, ne, 1), check("edd", s.edd, ne, 1), check("sig", s.sig, ne, 1);
    hasDx = hasDx && s.dx.size() > 0;
    hasDe = hasDe && s.de.size() > 0;
    hasD = hasD && s.bigd.size() > 0;
    if (s.dx.size()) check("dx", s.dx, nx, L.ndof());
    if (s.de.size()) check("de", s.de, ne, L.ndof());
    if (s.bigd.size()) check("bigd", s.bigd, ne, nx);
    if (s.M0.size()) {
      if (!hasSys) m = s.M0.rows();
      hasSys = true;
      for (auto [name, A] :
           {std::pair{"M0", &s.M0}, {"K0", &s.K0}, {"G0", &s.G0}, {"C0", &s.C0}, {"D0", &s.D0}, {"N0", &s.N0}})
        check(name, *A, m, m);
    }
    if (s.K0B.size() || s.M0all.size()) {
      check("M0 (.ltv)", s.M0all, L.ndof(), L.ndof());
      check("K0B", s.K0B, L.ndof(), L.ndof());
    }
    nev = std::max<std::size_t>(nev, s.freq.size());
    if (s.freq.size()) check("freq", s.freq, s.freq.size(), 1);
    if (s.modeq.size()) check("modeq", s.modeq, s.modeq.rows(), s.freq.size());
    if (s.modex.size()) check("modex", s.modex, nx, s.freq.size());
  }

  hasK0B = nt > 0;
  for (const auto& st : r.steps) hasK0B = hasK0B && st.K0B.size() > 0;
  if (r.stateSpace) {
    const SpacarStateSpace& ss = *r.stateSpace;
    const auto n = ss.A.rows(), ni = ss.B.cols(), no = ss.C.rows();
    auto checkSs = [&](const char* name, const Eigen::MatrixXd& v, Eigen::Index rows, Eigen::Index cols) {
      if (v.rows() != rows || v.cols() != cols)
        throw std::invalid_argument("SPACAR results '" + base + "': state-space " + name + " is " +
                                    std::to_string(v.rows()) + " x " + std::to_string(v.cols()) + ", expected " +
                                    std::to_string(rows) + " x " + std::to_string(cols));
      if (!v.allFinite()) throw std::invalid_argument("SPACAR results '" + base + "': non-finite state-space " + name);
    };
    checkSs("A", ss.A, n, n), checkSs("B", ss.B, n, ni), checkSs("C", ss.C, no, n), checkSs("D", ss.D, no, ni);
    if (ss.inputNames.size() != static_cast<std::size_t>(ni) || ss.outputNames.size() != static_cast<std::size_t>(no))
      throw std::invalid_argument("SPACAR results '" + base + "': one name per state-space input and output expected");
  }
  return c;
}

void writeSpacarStateSpace(MatSink& w, const SpacarStateSpace& ss) {
  w.matrix("A", ss.A);
  w.matrix("B", ss.B);
  w.matrix("C", ss.C);
  w.matrix("D", ss.D);
  w.scalar("DFT", ss.D.size() && !ss.D.isZero(0.0) ? 1.0 : 0.0);
}

// <base>.sbd: counts, topology, element constants and the per-step x, e, sig, ... (and dx, bigd).
void writeSbd(MatSink& w, const core::Model& model, const SpacarResults& r, const SpacarLayout& L,
              const SpacarContents& c) {
  const std::size_t nt = r.time.size(), nx = model.nx, ne = model.ne;
  const bool hasFx = c.hasFx, hasDx = c.hasDx, hasD = c.hasD;
  // Counts.
  w.scalar("mode", r.mode);
  w.scalar("nx", static_cast<double>(nx));
  w.scalar("ne", static_cast<double>(ne));
  w.write("nxp", 1, 4, {double(L.nxp[0]), double(L.nxp[1]), double(L.nxp[2]), double(L.nxp[3])});
  w.write("nep", 1, 4, {double(L.nep[0]), double(L.nep[1]), double(L.nep[2]), double(L.nep[3])});
  w.scalar("ndof", L.ndof());
  w.scalar("nddof", L.nddof());
  w.scalar("tdef", static_cast<double>(nt));
  const SpacarTopology T = spacarTopology(model, L);
  const Eigen::MatrixXd &lnp = T.lnp, &ln = T.ln, &le = T.le, &it = T.it, &rl0 = T.rl0;
  w.matrix("lnp", lnp);
  w.matrix("ln", ln);
  w.matrix("le", le);
  w.matrix("it", it);
  w.matrix("rl0", rl0);
  w.matrix("rxyz", spacarElementTriads(model, le.rows(), 0));
  w.matrix("rxyzq", spacarElementTriads(model, le.rows(), 1));
  w.matrix("estiff", spacarElementConstants(model, ElementConstant::Stiffness, le.rows()));
  w.matrix("stif", spacarElementConstants(model, ElementConstant::Stiffness, le.rows(), 6));
  w.matrix("edamp", spacarElementConstants(model, ElementConstant::Damping, le.rows()));
  w.matrix("em", spacarElementConstants(model, ElementConstant::Mass, le.rows()));
  w.matrix("esig", spacarElementPrestress(model, le.rows()));
  w.matrix("x0", L.sortX(model.x0));
  // Per step: one row per stored step. `t` is SPACAR's name of the time (its spadraw reads it).
  w.write("time", nt, 1, std::vector<double>(r.time.begin(), r.time.end()));
  w.write("t", nt, 1, std::vector<double>(r.time.begin(), r.time.end()));
  auto rows = [&](const char* name, Eigen::VectorXd SpacarStep::*member, std::size_t n) {
    std::vector<double> data(nt * n);
    for (std::size_t k = 0; k < nt; ++k)
      for (std::size_t j = 0; j < n; ++j) data[j * nt + k] = (r.steps[k].*member)[j];
    w.write(name, nt, n, std::move(data));
  };
  rows("x", &SpacarStep::x, nx), rows("xd", &SpacarStep::xd, nx), rows("xdd", &SpacarStep::xdd, nx);
  rows("e", &SpacarStep::e, ne), rows("ed", &SpacarStep::ed, ne), rows("edd", &SpacarStep::edd, ne);
  rows("sig", &SpacarStep::sig, ne), rows("fxt", &SpacarStep::fxt, nx);
  if (hasFx) rows("fx", &SpacarStep::fx, nx), rows("fxgrav", &SpacarStep::fxgrav, nx);
  auto pages = [&](const char* name, Eigen::MatrixXd SpacarStep::*member, std::size_t a, std::size_t b) {
    std::vector<double> data;
    data.reserve(a * b * nt);
    for (std::size_t k = 0; k < nt; ++k) {
      const Eigen::MatrixXd& A = r.steps[k].*member;
      data.insert(data.end(), A.data(), A.data() + A.size());
    }
    w.write(name, a, b, std::move(data), nt);
  };
  if (hasDx) pages("dx", &SpacarStep::dx, nx, L.ndof());
  if (c.hasDe) pages("de", &SpacarStep::de, ne, L.ndof());
  if (hasD) pages("bigd", &SpacarStep::bigd, ne, nx);
  w.scalar("nsteps", static_cast<double>(r.nsteps));
  w.scalar("nfailed", static_cast<double>(r.nfailed));
  w.scalar("nfevals", static_cast<double>(r.nfevals));
}

// <base>.sbm: the linearised matrices, frequencies and modes per step (and the state-space model).
void writeSbm(MatSink& w, const core::Model& model, const SpacarResults& r, const SpacarLayout& L,
              const SpacarContents& c) {
  const std::size_t nt = r.time.size(), nx = model.nx, m = c.m, nev = c.nev;
  w.write("time", nt, 1, std::vector<double>(r.time.begin(), r.time.end()));
  w.write("t", nt, 1, std::vector<double>(r.time.begin(), r.time.end()));
  w.scalar("tdef", static_cast<double>(nt));
  w.scalar("ndof", L.ndof());  // SPACAR's loadsbm lists them among the .sbm's variables
  w.scalar("nddof", L.nddof());
  if (c.hasSys) {
    for (auto [name, member] : {std::pair{"M0", &SpacarStep::M0},
                                {"K0", &SpacarStep::K0},
                                {"G0", &SpacarStep::G0},
                                {"C0", &SpacarStep::C0},
                                {"D0", &SpacarStep::D0},
                                {"N0", &SpacarStep::N0}}) {
      std::vector<double> data(m * m * nt, 0.0);
      for (std::size_t k = 0; k < nt; ++k) {
        const Eigen::MatrixXd& A = r.steps[k].*member;
        if (A.size()) std::copy(A.data(), A.data() + A.size(), data.begin() + static_cast<std::ptrdiff_t>(k * m * m));
      }
      w.write(name, m, m, std::move(data), nt);
    }
  }
  std::vector<double> f(nt * nev, 0.0);
  for (std::size_t k = 0; k < nt; ++k)
    for (Eigen::Index i = 0; i < r.steps[k].freq.size(); ++i) f[i * nt + k] = r.steps[k].freq[i];
  w.write("freq", nt, nev, std::move(f));
  std::size_t mq = 0;
  // modeq and modex each when every step has them (a refined model's results at its original nodes
  // have modex alone: io/formats/OriginalResults.hpp).
  bool hasModeq = nt > 0, hasModex = nt > 0;
  for (const auto& s : r.steps) {
    hasModeq = hasModeq && s.modeq.size() > 0 && static_cast<std::size_t>(s.modeq.cols()) == nev;
    hasModex = hasModex && s.modex.size() > 0 && static_cast<std::size_t>(s.modex.cols()) == nev;
    mq = std::max<std::size_t>(mq, s.modeq.rows());
  }
  std::vector<double> q, xm;
  for (const auto& s : r.steps) {
    if (hasModeq) q.insert(q.end(), s.modeq.data(), s.modeq.data() + s.modeq.size());
    if (hasModex) xm.insert(xm.end(), s.modex.data(), s.modex.data() + s.modex.size());
  }
  if (hasModeq && q.size() == mq * nev * nt) w.write("modeq", mq, nev, std::move(q), nt);
  if (hasModex && xm.size() == nx * nev * nt) w.write("modex", nx, nev, std::move(xm), nt);
  if (r.stateSpace) writeSpacarStateSpace(w, *r.stateSpace);
}

// <base>.ltv: the transfer function's state-space model, or M0 and K0B over every kinematic degree
// of freedom per step (mode 3 on a static file).
void writeLtv(MatSink& w, const SpacarResults& r, const SpacarLayout& L) {
  const std::size_t nt = r.time.size();
  if (r.stateSpace) {
    // One step: the state-space model of the last load step (getss reads step 1).
    w.scalar("tdef", 1.0);
    writeSpacarStateSpace(w, *r.stateSpace);
    w.text("inputnames", r.stateSpace->inputNames);
    w.text("outputnames", r.stateSpace->outputNames);
  } else {
    w.write("time", nt, 1, std::vector<double>(r.time.begin(), r.time.end()));
    w.scalar("tdef", static_cast<double>(nt));
    const std::size_t n = L.ndof();
    for (auto [name, member] : {std::pair{"M0", &SpacarStep::M0all}, {"K0B", &SpacarStep::K0B}}) {
      std::vector<double> data;
      data.reserve(n * n * nt);
      for (const auto& st : r.steps) data.insert(data.end(), (st.*member).data(), (st.*member).data() + n * n);
      w.write(name, n, n, std::move(data), nt);
    }
  }
}

}  // namespace

namespace {

// The files of a result set and what goes into each: fill(sink, i) writes file i's variables.
struct SpacarFilePlan {
  SpacarLayout L;
  SpacarContents c;
  std::vector<std::string> paths;
};
SpacarFilePlan planSpacarFiles(const std::string& base, const core::Model& model, const SpacarResults& r) {
  SpacarFilePlan plan;
  plan.L = spacarLayout(model);
  const std::size_t nt = r.time.size();
  if (r.steps.size() != nt)
    throw std::invalid_argument("SPACAR results '" + base + "': " + std::to_string(nt) + " times, " +
                                std::to_string(r.steps.size()) + " steps");
  plan.c = checkSpacarResults(base, model, r, plan.L);
  plan.paths.push_back(base + ".sbd");
  if (plan.c.hasSys || plan.c.nev > 0) plan.paths.push_back(base + ".sbm");
  if (r.stateSpace || plan.c.hasK0B) plan.paths.push_back(base + ".ltv");
  return plan;
}
void fillSpacarFile(MatSink& w, const std::string& path, const SpacarFilePlan& plan, const core::Model& model,
                    const SpacarResults& r) {
  const std::string ext = path.substr(path.size() - 4);
  if (ext == ".sbd") {
    writeSbd(w, model, r, plan.L, plan.c);
    for (const auto& v : r.extraSbd) {
      if (v.isText)
        w.text(v.name.c_str(), v.text);
      else
        w.write(v.name.c_str(), v.dims.at(0), v.dims.at(1), v.data, v.dims.size() > 2 ? v.dims[2] : 1);
    }
  } else if (ext == ".sbm")
    writeSbm(w, model, r, plan.L, plan.c);
  else
    writeLtv(w, r, plan.L);
}

}  // namespace

std::vector<std::string> writeSpacarResults(const std::string& base, const core::Model& model, const SpacarResults& r) {
  if (model.unrefined) return writeSpacarResults(base, *model.unrefined, originalSpacarResults(model, r));
  const SpacarFilePlan plan = planSpacarFiles(base, model, r);
  for (const auto& path : plan.paths) {
    MatWriter w(path);
    fillSpacarFile(w, path, plan, model, r);
    w.close();
  }
  return plan.paths;
}

std::vector<SpacarFileContents> spacarResultFiles(const std::string& base, const core::Model& model,
                                                  const SpacarResults& r) {
  if (model.unrefined) return spacarResultFiles(base, *model.unrefined, originalSpacarResults(model, r));
  const SpacarFilePlan plan = planSpacarFiles(base, model, r);
  std::vector<SpacarFileContents> files(plan.paths.size());
  for (std::size_t i = 0; i < plan.paths.size(); ++i) {
    files[i].path = plan.paths[i];
    MatCollector w(files[i]);
    fillSpacarFile(w, plan.paths[i], plan, model, r);
  }
  return files;
}

void writeSpacarFile(const SpacarFileContents& file) {
  try {
    MatWriter w(file.path);
    for (const auto& v : file.variables) {
      if (v.isText)
        w.text(v.name.c_str(), v.text);
      else
        w.write(v.name.c_str(), v.dims.at(0), v.dims.at(1), v.data, v.dims.size() > 2 ? v.dims[2] : 1);
    }
    w.close();
  } catch (...) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(file.path, ec)) std::filesystem::remove(file.path, ec);  // no half file
    throw;
  }
}

}  // namespace flexmb::io
