#include "io/formats/ResultWriter.hpp"

#include <matio.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

#include "core/elements/EulerParameters.hpp"
#include "io/formats/OriginalResults.hpp"
#include "text/NumberText.hpp"

namespace flexmb::io {
namespace {

using core::Model;
using core::StateOutputs;
using core::Trajectory;

// ---------------------------------------------------------------------------------------------
// Number formatting (locale-independent).

using text::appendG17;

// ---------------------------------------------------------------------------------------------
// Files.

class OutFile {
 public:
  explicit OutFile(std::string path) : path_(std::move(path)) {
    errno = 0;
    f_ = std::fopen(path_.c_str(), "wb");
    if (!f_)
      throw std::runtime_error("cannot open '" + path_ +
                               "' for writing: " + (errno ? std::strerror(errno) : "unknown error"));
  }
  OutFile(const OutFile&) = delete;
  OutFile& operator=(const OutFile&) = delete;
  ~OutFile() {
    if (f_) std::fclose(f_);
  }
  void write(std::string_view s) {
    if (s.empty()) return;
    errno = 0;
    if (std::fwrite(s.data(), 1, s.size(), f_) != s.size())
      throw std::runtime_error("error writing '" + path_ + "': " + (errno ? std::strerror(errno) : "short write"));
  }
  void close() {
    errno = 0;
    const bool bad = std::ferror(f_) != 0;
    const int rc = std::fclose(f_);
    f_ = nullptr;
    if (bad || rc != 0)
      throw std::runtime_error("error writing '" + path_ + "': " + (errno ? std::strerror(errno) : "write failed"));
  }

 private:
  std::string path_;
  std::FILE* f_ = nullptr;
};

// ---------------------------------------------------------------------------------------------
// Input checks.

struct Quantity {
  const char* name;
  Eigen::VectorXd StateOutputs::*member;
  bool nodal;  // size nx (true) or ne (false)
};

constexpr Quantity kQuantities[] = {
    {"x", &StateOutputs::x, true},      {"xd", &StateOutputs::xd, true},  {"xdd", &StateOutputs::xdd, true},
    {"e", &StateOutputs::e, false},     {"ed", &StateOutputs::ed, false}, {"edd", &StateOutputs::edd, false},
    {"sig", &StateOutputs::sig, false},
};

void checkTime(double t, const std::string& where) {
  if (!std::isfinite(t)) throw std::runtime_error(where + ": non-finite output time " + text::g17(t));
}

// Sizes and finiteness of one state; `where` names the writer and the path for messages.
void checkState(const StateOutputs& s, double t, const Model& model, const std::vector<std::string>& xNames,
                const std::vector<std::string>& eNames, const std::string& where) {
  for (const Quantity& q : kQuantities) {
    const Eigen::VectorXd& v = s.*q.member;
    const int n = q.nodal ? model.nx : model.ne;
    if (v.size() != n)
      throw std::runtime_error(where + ": " + q.name + " at t = " + text::g17(t) + " has " + std::to_string(v.size()) +
                               " entries, the model has " + std::to_string(n));
    const std::vector<std::string>& names = q.nodal ? xNames : eNames;
    for (int j = 0; j < n; ++j)
      if (!std::isfinite(v[j]))
        throw std::runtime_error(where + ": non-finite value " + text::g17(v[j]) + " in " + q.name + " at t = " +
                                 text::g17(t) + ", column " + std::to_string(j + 1) + " (" + names[j] + ")");
  }
}

void checkTrajectory(const Trajectory& traj, const Model& model, const std::vector<std::string>& xNames,
                     const std::vector<std::string>& eNames, const std::string& where) {
  if (traj.time.size() != traj.states.size())
    throw std::runtime_error(where + ": trajectory has " + std::to_string(traj.time.size()) + " output times but " +
                             std::to_string(traj.states.size()) + " states");
  for (std::size_t i = 0; i < traj.time.size(); ++i) {
    checkTime(traj.time[i], where);
    checkState(traj.states[i], traj.time[i], model, xNames, eNames, where);
  }
}

std::string sanitize(const std::string& s) {
  std::string r = s;
  for (char& c : r)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  return r;
}

// e index -> (element index, 0-based component); -1 when no element owns it.
std::vector<std::pair<int, int>> deformationOwners(const Model& model) {
  std::vector<std::pair<int, int>> owner(static_cast<std::size_t>(std::max(model.ne, 0)), {-1, 0});
  for (std::size_t k = 0; k < model.elements.size(); ++k) {
    const core::ElementEntry& el = model.elements[k];
    if (!el.type) continue;
    const int nd = el.type->numDeformations();
    for (int c = 0; c < nd; ++c) {
      const int j = el.firstDef + c;
      if (j >= 0 && j < model.ne) owner[j] = {static_cast<int>(k), c};
    }
  }
  return owner;
}

// Labels and first coordinates of the Euler-parameter nodes, in model order.
std::vector<const core::Node*> eulerNodes(const Model& model) {
  std::vector<const core::Node*> r;
  for (const core::Node& n : model.nodes)
    if (n.kind == core::NodeKind::EulerParameters) r.push_back(&n);
  return r;
}

// Rotation matrix and rotation vector of the Euler parameters at x[first .. first+3], normalised
// first (the integrator keeps |lambda| = 1 only to its tolerance).
void orientation(const Eigen::VectorXd& x, int first, Eigen::Matrix3d& R, Eigen::Vector3d& rv) {
  Eigen::Vector4d l = x.segment<4>(first);
  l /= l.norm();
  if (l[0] < 0.0) l = -l;  // the same rotation; angle in [0, pi]
  R = core::euler::rotation(l);
  const double s = l.tail<3>().norm();
  const double angle = 2.0 * std::atan2(s, l[0]);
  rv = s > 0.0 ? Eigen::Vector3d(l.tail<3>() * (angle / s)) : Eigen::Vector3d::Zero();
}

// ---------------------------------------------------------------------------------------------
// matio.

struct MatFile {
  mat_t* mat = nullptr;
  ~MatFile() {
    if (mat) Mat_Close(mat);
  }
};

// Writes an nrows x ncols double matrix; data column-major (size nrows*ncols).
void writeMatVar(mat_t* mat, const std::string& path, const char* name, std::size_t nrows, std::size_t ncols,
                 std::vector<double>& data, std::size_t npages = 0) {
  size_t dims[3] = {nrows, ncols, npages};
  static double dummy = 0.0;  // matio wants a non-null pointer even for empty matrices
  double* ptr = data.empty() ? &dummy : data.data();
  matvar_t* var = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, npages > 0 ? 3 : 2, dims, ptr, MAT_F_DONT_COPY_DATA);
  if (!var) throw std::runtime_error("cannot write '" + path + "': matio could not create variable '" + name + "'");
  const int rc = Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE);
  Mat_VarFree(var);
  if (rc != 0) throw std::runtime_error("cannot write '" + path + "': matio failed to write variable '" + name + "'");
}

}  // namespace

// -------------------------------------------------------------------------------------------------

std::vector<std::string> coordinateColumnNames(const Model& model) {
  std::vector<std::string> names(static_cast<std::size_t>(std::max(model.nx, 0)));
  for (const core::Node& n : model.nodes) {
    std::string base = "node";
    base += std::to_string(n.label);
    if (n.kind == core::NodeKind::Warping) {  // BEAMW: the rate of twist
      if (n.firstCoord >= 0 && n.firstCoord < model.nx) names[n.firstCoord] = base + ".w";
    } else if (core::isSpatial(n.kind)) {
      for (int c = 0; c < n.dim(); ++c)
        names[n.firstCoord + c] = base + (n.kind == core::NodeKind::EulerParameters ? ".lambda" + std::to_string(c)
                                                                                    : std::string(".") + "xyz"[c]);
    } else if (n.kind == core::NodeKind::Orientation) {
      if (n.firstCoord >= 0 && n.firstCoord < model.nx) names[n.firstCoord] = base + ".angle";
    } else {
      if (n.firstCoord >= 0 && n.firstCoord < model.nx) names[n.firstCoord] = base + ".x";
      if (n.firstCoord + 1 >= 0 && n.firstCoord + 1 < model.nx) names[n.firstCoord + 1] = base + ".y";
    }
  }
  for (std::size_t j = 0; j < names.size(); ++j)
    if (names[j].empty()) names[j] = std::string("x").append(std::to_string(j + 1));
  return names;
}

std::vector<std::string> deformationColumnNames(const Model& model) {
  const auto owner = deformationOwners(model);
  std::vector<std::string> names(owner.size());
  for (std::size_t j = 0; j < owner.size(); ++j) {
    const auto [k, c] = owner[j];
    if (k < 0) {
      names[j] = std::string("e").append(std::to_string(j + 1));
      continue;
    }
    const core::ElementEntry& el = model.elements[k];
    names[j] = el.type->keyword + std::to_string(el.label) + ".e" + std::to_string(c + 1) + "_" +
               sanitize(el.type->deformationNames[c]);
  }
  return names;
}

std::vector<std::string> writeCsv(const std::string& prefix, const Model& model, const Trajectory& traj) {
  if (model.unrefined) return writeCsv(prefix, *model.unrefined, originalTrajectory(model, traj));
  const auto xNames = coordinateColumnNames(model);
  const auto eNames = deformationColumnNames(model);
  checkTrajectory(traj, model, xNames, eNames, "CSV output '" + prefix + "_*.csv'");

  std::vector<std::string> written;
  for (const Quantity& q : kQuantities) {
    const std::string path = prefix + "_" + q.name + ".csv";
    const std::vector<std::string>& names = q.nodal ? xNames : eNames;
    OutFile f(path);
    std::string line = "time";
    for (const std::string& n : names) {
      line += ',';
      line += n;
    }
    line += '\n';
    f.write(line);
    for (std::size_t i = 0; i < traj.time.size(); ++i) {
      line.clear();
      appendG17(line, traj.time[i]);
      const Eigen::VectorXd& v = traj.states[i].*q.member;
      for (Eigen::Index j = 0; j < v.size(); ++j) {
        line += ',';
        appendG17(line, v[j]);
      }
      line += '\n';
      f.write(line);
    }
    f.close();
    written.push_back(path);
  }
  return written;
}

bool hasOrientationNodes(const Model& model) { return !eulerNodes(model).empty(); }

void writeMatrixCsv(const std::string& path, const Eigen::MatrixXd& A, const std::vector<std::string>& rowNames,
                    const std::vector<std::string>& colNames, const std::string& corner) {
  if (rowNames.size() != static_cast<std::size_t>(A.rows()) || colNames.size() != static_cast<std::size_t>(A.cols()))
    throw std::invalid_argument(path + ": " + std::to_string(A.rows()) + " x " + std::to_string(A.cols()) +
                                " matrix with " + std::to_string(rowNames.size()) + " row and " +
                                std::to_string(colNames.size()) + " column names");
  if (!A.allFinite()) throw std::invalid_argument(path + ": the matrix holds a non-finite value");
  auto quoted = [](const std::string& s) {
    if (s.find_first_of(",\"") == std::string::npos) return s;
    std::string q(1, '"');
    for (char c : s) {
      q += c;
      if (c == '"') q += '"';  // a quote doubled, as CSV escapes it
    }
    q += '"';
    return q;
  };
  OutFile f(path);
  std::string line = quoted(corner);
  for (const auto& c : colNames) (line += ',') += quoted(c);
  line += "\n";
  f.write(line);
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    line = quoted(rowNames[i]);
    for (Eigen::Index j = 0; j < A.cols(); ++j) {
      line += ',';
      appendG17(line, A(i, j));
    }
    line += '\n';
    f.write(line);
  }
  f.close();
}

std::string writeOrientationCsv(const std::string& prefix, const Model& model, const Trajectory& traj) {
  if (model.unrefined) return writeOrientationCsv(prefix, *model.unrefined, originalTrajectory(model, traj));
  const auto nodes = eulerNodes(model);
  if (nodes.empty()) return "";
  const auto xNames = coordinateColumnNames(model);
  const auto eNames = deformationColumnNames(model);
  const std::string path = prefix + "_rot.csv";
  checkTrajectory(traj, model, xNames, eNames, "CSV output '" + path + "'");
  OutFile f(path);
  std::string line = "time";
  for (const core::Node* n : nodes) {
    const std::string base = ",node" + std::to_string(n->label) + ".";
    for (const char* c : {"rx", "ry", "rz"}) line += base + c;
    for (int i = 1; i <= 3; ++i)
      for (int j = 1; j <= 3; ++j) line += base + "R" + std::to_string(i) + std::to_string(j);
  }
  line += '\n';
  f.write(line);
  Eigen::Matrix3d R;
  Eigen::Vector3d rv;
  for (std::size_t k = 0; k < traj.time.size(); ++k) {
    line.clear();
    appendG17(line, traj.time[k]);
    for (const core::Node* n : nodes) {
      orientation(traj.states[k].x, n->firstCoord, R, rv);
      for (int c = 0; c < 3; ++c) line += ',', appendG17(line, rv[c]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) line += ',', appendG17(line, R(i, j));
    }
    line += '\n';
    f.write(line);
  }
  f.close();
  return path;
}

void writeMat(const std::string& path, const Model& model, const Trajectory& traj) {
  if (model.unrefined) return writeMat(path, *model.unrefined, originalTrajectory(model, traj));
  const auto xNames = coordinateColumnNames(model);
  const auto eNames = deformationColumnNames(model);
  checkTrajectory(traj, model, xNames, eNames, "MAT output '" + path + "'");

  // Probe the path with stdio first: matio reports failures without a reason.
  {
    OutFile probe(path);
    probe.close();
  }

  MatFile mf;
  mf.mat = Mat_CreateVer(path.c_str(), kMatHeader, MAT_FT_MAT5);
  if (!mf.mat) throw std::runtime_error("cannot write '" + path + "': matio could not create the MAT file");

  const std::size_t nt = traj.time.size();
  std::vector<double> data(traj.time.begin(), traj.time.end());
  writeMatVar(mf.mat, path, "time", nt, 1, data);

  for (const Quantity& q : kQuantities) {
    const std::size_t n = static_cast<std::size_t>(q.nodal ? model.nx : model.ne);
    data.assign(nt * n, 0.0);
    for (std::size_t i = 0; i < nt; ++i) {
      const Eigen::VectorXd& v = traj.states[i].*q.member;
      for (std::size_t j = 0; j < n; ++j) data[j * nt + i] = v[static_cast<Eigen::Index>(j)];
    }
    writeMatVar(mf.mat, path, q.name, nt, n, data);
  }

  if (const auto nodes = eulerNodes(model); !nodes.empty()) {
    const std::size_t nr = nodes.size();
    data.clear();
    for (const core::Node* n : nodes) data.push_back(n->label);
    writeMatVar(mf.mat, path, "rotnodes", 1, nr, data);
    std::vector<double> rv(nt * 3 * nr), rm(nt * 9 * nr);
    Eigen::Matrix3d R;
    Eigen::Vector3d v;
    for (std::size_t i = 0; i < nt; ++i)
      for (std::size_t a = 0; a < nr; ++a) {
        orientation(traj.states[i].x, nodes[a]->firstCoord, R, v);
        for (std::size_t c = 0; c < 3; ++c) rv[(3 * a + c) * nt + i] = v[static_cast<Eigen::Index>(c)];
        for (std::size_t c = 0; c < 9; ++c) rm[(9 * a + c) * nt + i] = R.data()[c];  // column-major R(:)
      }
    writeMatVar(mf.mat, path, "rotvec", nt, 3 * nr, rv);
    writeMatVar(mf.mat, path, "rotmat", nt, 9 * nr, rm);
  }

  std::vector<std::pair<const char*, long>> stats = {
      {"nsteps", traj.nsteps}, {"nfailed", traj.nfailed}, {"nfevals", traj.nfevals}};
  if (traj.integrator != "ode45") {  // the implicit integrators' own counts (bdf, galpha, auto's switch)
    stats.emplace_back("njacevals", traj.njacevals);
    stats.emplace_back("nlinsetups", traj.nlinsetups);
  }
  for (const auto& [name, value] : stats) {
    data.assign(1, static_cast<double>(value));
    writeMatVar(mf.mat, path, name, 1, 1, data);
  }

  const int rc = Mat_Close(mf.mat);
  mf.mat = nullptr;
  if (rc != 0) throw std::runtime_error("cannot write '" + path + "': matio failed to close it");
}

void writeLinearizedMat(const std::string& path, const std::vector<double>& time,
                        const std::vector<core::LinearizedSystem>& sys, const std::vector<Eigen::VectorXd>& omega) {
  const std::size_t nt = time.size();
  if (sys.size() != nt || omega.size() != nt)
    throw std::invalid_argument("linearised MAT output '" + path + "': " + std::to_string(nt) + " times, " +
                                std::to_string(sys.size()) + " matrix sets, " + std::to_string(omega.size()) +
                                " frequency sets");
  using Member = const Eigen::MatrixXd core::LinearizedSystem::*;
  const std::pair<const char*, Member> mats[] = {
      {"M0", &core::LinearizedSystem::M}, {"K0", &core::LinearizedSystem::K}, {"G0", &core::LinearizedSystem::G},
      {"C0", &core::LinearizedSystem::C}, {"D0", &core::LinearizedSystem::D}, {"N0", &core::LinearizedSystem::N}};
  const std::size_t m = nt ? static_cast<std::size_t>(sys[0].M.rows()) : 0;
  std::size_t nev = 0;
  for (std::size_t k = 0; k < nt; ++k) {
    nev = std::max(nev, static_cast<std::size_t>(omega[k].size()));
    for (const auto& [name, member] : mats) {
      const Eigen::MatrixXd& A = sys[k].*member;
      if (static_cast<std::size_t>(A.rows()) != m || static_cast<std::size_t>(A.cols()) != m)
        throw std::invalid_argument("linearised MAT output '" + path + "': " + name + " at t = " + text::g17(time[k]) +
                                    " is not " + std::to_string(m) + " x " + std::to_string(m));
      if (!A.allFinite())
        throw std::invalid_argument("linearised MAT output '" + path + "': non-finite " + name +
                                    " at t = " + text::g17(time[k]));
    }
  }
  {
    OutFile probe(path);
    probe.close();
  }
  MatFile mf;
  mf.mat = Mat_CreateVer(path.c_str(), kMatHeader, MAT_FT_MAT5);
  if (!mf.mat) throw std::runtime_error("cannot write '" + path + "': matio could not create the MAT file");
  std::vector<double> data(time.begin(), time.end());
  writeMatVar(mf.mat, path, "time", nt, 1, data);
  for (const auto& [name, member] : mats) {
    // m x m x nt, column-major: A(:,:,k) is the matrix at time(k).
    data.resize(m * m * nt);
    for (std::size_t k = 0; k < nt; ++k) {
      const Eigen::MatrixXd& A = sys[k].*member;
      std::copy(A.data(), A.data() + m * m, data.begin() + static_cast<std::ptrdiff_t>(k * m * m));
    }
    writeMatVar(mf.mat, path, name, m, m, data, nt);
  }
  // Natural frequencies in Hz (nt x nev); NaN where fewer were found is not allowed, so pad with 0.
  data.assign(nt * nev, 0.0);
  for (std::size_t k = 0; k < nt; ++k)
    for (std::size_t i = 0; i < static_cast<std::size_t>(omega[k].size()); ++i)
      data[i * nt + k] = omega[k][static_cast<Eigen::Index>(i)] / (2 * M_PI);
  writeMatVar(mf.mat, path, "freq", nt, nev, data);
  const int rc = Mat_Close(mf.mat);
  mf.mat = nullptr;
  if (rc != 0) throw std::runtime_error("cannot write '" + path + "': matio failed to close it");
}

}  // namespace flexmb::io
