// Result writers (io/formats/ResultWriter): CSV tables, MATLAB .mat (read back with scipy), .dat echo,
// and their error paths. The model is built by hand (no reader, no element evaluation needed).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "io/formats/ResultWriter.hpp"

namespace fs = std::filesystem;
using flexmb::core::ElementEntry;
using flexmb::core::ElementTypeInfo;
using flexmb::core::Model;
using flexmb::core::Node;
using flexmb::core::NodeKind;
using flexmb::core::Role;
using flexmb::core::StateOutputs;
using flexmb::core::Trajectory;

namespace {

const ElementTypeInfo& beamType() {
  static const ElementTypeInfo info = [] {
    ElementTypeInfo t;
    t.keyword = "PLBEAM";
    t.slots = {NodeKind::Position, NodeKind::Orientation, NodeKind::Position, NodeKind::Orientation};
    t.deformationNames = {"elongation", "bending p", "bending q"};
    t.create = nullptr;
    return t;
  }();
  return info;
}

const ElementTypeInfo& hingeType() {
  static const ElementTypeInfo info = [] {
    ElementTypeInfo t;
    t.keyword = "PLHINGE";
    t.slots = {NodeKind::Orientation, NodeKind::Orientation};
    t.deformationNames = {"relative rotation"};
    t.create = nullptr;
    return t;
  }();
  return info;
}

// Nodes 3 (xy), 103 (angle), 4 (xy), 104 (angle): nx = 6.
// PLBEAM 5 (3 103 4 104): e1..e3; PLHINGE 7 (103 104): e4. ne = 4.
// DYNE 5 2 and DYNE 7 1 (e indices 1 and 3).
Model makeModel() {
  Model m;
  m.sourceFile = "hand.dat";
  auto addNode = [&](int label, NodeKind kind, int first) {
    Node n;
    n.label = label;
    n.kind = kind;
    n.firstCoord = first;
    m.nodeByLabel[label] = static_cast<int>(m.nodes.size());
    m.nodes.push_back(n);
  };
  addNode(3, NodeKind::Position, 0);
  addNode(103, NodeKind::Orientation, 2);
  addNode(4, NodeKind::Position, 3);
  addNode(104, NodeKind::Orientation, 5);
  m.nx = 6;
  m.xOwnerNode = {0, 0, 1, 2, 2, 3};
  m.xRole.assign(6, Role::Calculable);
  m.x0 = Eigen::VectorXd::Zero(6);

  ElementEntry beam;
  beam.label = 5;
  beam.type = &beamType();
  beam.nodes = {0, 1, 2, 3};
  beam.coords = {0, 1, 2, 3, 4, 5};
  beam.firstDef = 0;
  ElementEntry hinge;
  hinge.label = 7;
  hinge.type = &hingeType();
  hinge.nodes = {1, 3};
  hinge.coords = {2, 5};
  hinge.firstDef = 3;
  m.elementByLabel[5] = 0;
  m.elementByLabel[7] = 1;
  m.elements = {beam, hinge};
  m.ne = 4;
  m.eOwnerElement = {0, 0, 0, 1};
  m.eRole = {Role::Fixed, Role::Dynamic, Role::Fixed, Role::Dynamic};
  m.dofs = {{true, 1}, {true, 3}};
  return m;
}

// Distinct, full-mantissa values with both signs and a wide exponent range.
double value(int quantity, int row, int col) {
  double v = (quantity + 1) * 100.0 + row + col / 10.0 + std::sqrt(2.0) / (quantity + row + col + 3);
  if (col % 2 == 1) v = -v;
  if (col == 2) v *= 1e-20;
  if (col == 3) v *= 1e+15;
  return v;
}

Trajectory makeTrajectory(const Model& m, int nt = 4) {
  Trajectory tr;
  for (int i = 0; i < nt; ++i) {
    tr.time.push_back(0.1 * i + 1.0 / 3.0);
    StateOutputs s;
    Eigen::VectorXd* q[] = {&s.x, &s.xd, &s.xdd, &s.e, &s.ed, &s.edd, &s.sig};
    for (int k = 0; k < 7; ++k) {
      const int n = k < 3 ? m.nx : m.ne;
      q[k]->resize(n);
      for (int j = 0; j < n; ++j) (*q[k])[j] = value(k, i, j);
    }
    tr.states.push_back(s);
  }
  tr.nsteps = 123;
  tr.nfailed = 4;
  tr.nfevals = 745;
  return tr;
}

const char* kNames[] = {"x", "xd", "xdd", "e", "ed", "edd", "sig"};

const Eigen::VectorXd& member(const StateOutputs& s, int k) {
  const Eigen::VectorXd* q[] = {&s.x, &s.xd, &s.xdd, &s.e, &s.ed, &s.edd, &s.sig};
  return *q[k];
}

class ResultWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("flexmb_result_writer_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

std::string readFile(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string l;
  while (std::getline(in, l)) out.push_back(l);
  return out;
}

double parseExact(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  EXPECT_EQ(*end, '\0') << "trailing characters in number '" << s << "'";
  EXPECT_NE(end, s.c_str()) << "not a number: '" << s << "'";
  return v;
}

bool haveScipy() { return std::system("/usr/bin/python3 -c 'import scipy.io, numpy' >/dev/null 2>&1") == 0; }

std::string runCommand(const std::string& cmd, int& status) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) {
    status = -1;
    return out;
  }
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  status = ::pclose(p);
  return out;
}

}  // namespace

TEST(ResultWriterNames, ColumnNamesFollowModelLabels) {
  const Model m = makeModel();
  EXPECT_EQ(flexmb::io::coordinateColumnNames(m),
            (std::vector<std::string>{"node3.x", "node3.y", "node103.angle", "node4.x", "node4.y", "node104.angle"}));
  EXPECT_EQ(flexmb::io::deformationColumnNames(m),
            (std::vector<std::string>{"PLBEAM5.e1_elongation", "PLBEAM5.e2_bending_p", "PLBEAM5.e3_bending_q",
                                      "PLHINGE7.e1_relative_rotation"}));
}

TEST_F(ResultWriterTest, CsvHeadersAndExactValues) {
  const Model m = makeModel();
  const Trajectory tr = makeTrajectory(m);
  const std::string prefix = path("run");
  const auto files = flexmb::io::writeCsv(prefix, m, tr);
  ASSERT_EQ(files.size(), 7u);

  const std::vector<std::string> xHeader = {"time",    "node3.x", "node3.y",      "node103.angle",
                                            "node4.x", "node4.y", "node104.angle"};
  const std::vector<std::string> eHeader = {"time", "PLBEAM5.e1_elongation", "PLBEAM5.e2_bending_p",
                                            "PLBEAM5.e3_bending_q", "PLHINGE7.e1_relative_rotation"};
  for (int k = 0; k < 7; ++k) {
    const std::string expected = prefix + "_" + kNames[k] + ".csv";
    EXPECT_EQ(files[k], expected);
    ASSERT_TRUE(fs::exists(expected)) << expected;
    const auto ls = lines(readFile(expected));
    ASSERT_EQ(ls.size(), tr.time.size() + 1) << expected;
    EXPECT_EQ(split(ls[0], ','), k < 3 ? xHeader : eHeader) << expected;
    for (std::size_t i = 0; i < tr.time.size(); ++i) {
      const auto cells = split(ls[i + 1], ',');
      const Eigen::VectorXd& v = member(tr.states[i], k);
      ASSERT_EQ(cells.size(), static_cast<std::size_t>(v.size() + 1)) << expected << " row " << i;
      EXPECT_EQ(parseExact(cells[0]), tr.time[i]) << expected << " row " << i;
      for (Eigen::Index j = 0; j < v.size(); ++j)
        EXPECT_EQ(parseExact(cells[j + 1]), v[j]) << expected << " row " << i << " col " << j;
    }
  }
}

TEST_F(ResultWriterTest, MatReadsBackWithScipy) {
  if (!haveScipy())
    GTEST_SKIP() << "/usr/bin/python3 with scipy and numpy is not available "
                    "(apt-get install python3-scipy); cannot read the .mat file back";
  const Model m = makeModel();
  const Trajectory tr = makeTrajectory(m);
  const std::string mat = path("run.mat");
  const std::string prefix = path("run");
  flexmb::io::writeMat(mat, m, tr);
  flexmb::io::writeCsv(prefix, m, tr);
  ASSERT_TRUE(fs::exists(mat));

  // Python prints, per variable, "var <name> <dtype> <rows> <cols> <values row-major, repr>", and
  // per CSV quantity "csvdiff <name> <max |mat - csv|>" (time included).
  const std::string script = path("readback.py");
  {
    std::ofstream py(script);
    py << "import sys\n"
          "import numpy as np\n"
          "import scipy.io\n"
          "m = scipy.io.loadmat(sys.argv[1])\n"
          "names = ['time','x','xd','xdd','e','ed','edd','sig','nsteps','nfailed','nfevals']\n"
          "for n in names:\n"
          "    a = m[n]\n"
          "    print('var', n, a.dtype, a.shape[0], a.shape[1],\n"
          "          ' '.join(repr(float(v)) for v in a.flatten(order='C')))\n"
          "for n in names[1:8]:\n"
          "    c = np.loadtxt(sys.argv[2] + '_' + n + '.csv', delimiter=',', skiprows=1, ndmin=2)\n"
          "    if c.shape != (m[n].shape[0], m[n].shape[1] + 1):\n"
          "        print('csvshape', n, c.shape)\n"
          "        continue\n"
          "    d = max(np.max(np.abs(c[:, 1:] - m[n])), np.max(np.abs(c[:, 0] - m['time'][:, 0])))\n"
          "    print('csvdiff', n, repr(float(d)))\n";
  }
  int status = 0;
  const std::string out = runCommand("/usr/bin/python3 '" + script + "' '" + mat + "' '" + prefix + "' 2>&1", status);
  ASSERT_EQ(status, 0) << out;

  struct Var {
    std::string dtype;
    int rows = -1, cols = -1;
    std::vector<double> values;  // row-major
  };
  std::map<std::string, Var> vars;
  std::map<std::string, std::string> csvdiff;
  for (const std::string& l : lines(out)) {
    std::istringstream in(l);
    std::string tag, name;
    in >> tag >> name;
    if (tag == "var") {
      Var v;
      in >> v.dtype >> v.rows >> v.cols;
      std::string tok;
      while (in >> tok) v.values.push_back(parseExact(tok));
      vars[name] = v;
    } else if (tag == "csvdiff") {
      std::string d;
      in >> d;
      csvdiff[name] = d;
    } else {
      ADD_FAILURE() << "unexpected python output: " << l;
    }
  }

  const int nt = static_cast<int>(tr.time.size());
  ASSERT_TRUE(vars.count("time")) << out;
  EXPECT_EQ(vars["time"].dtype, "float64");
  EXPECT_EQ(vars["time"].rows, nt);
  EXPECT_EQ(vars["time"].cols, 1);
  ASSERT_EQ(vars["time"].values.size(), static_cast<std::size_t>(nt));
  for (int i = 0; i < nt; ++i) EXPECT_EQ(vars["time"].values[i], tr.time[i]);

  for (int k = 0; k < 7; ++k) {
    const std::string n = kNames[k];
    ASSERT_TRUE(vars.count(n)) << n << "\n" << out;
    const Var& v = vars[n];
    const int cols = k < 3 ? m.nx : m.ne;
    EXPECT_EQ(v.dtype, "float64") << n;
    ASSERT_EQ(v.rows, nt) << n;
    ASSERT_EQ(v.cols, cols) << n;
    ASSERT_EQ(v.values.size(), static_cast<std::size_t>(nt * cols)) << n;
    for (int i = 0; i < nt; ++i)
      for (int j = 0; j < cols; ++j)
        EXPECT_EQ(v.values[i * cols + j], member(tr.states[i], k)[j]) << n << "(" << i << "," << j << ")";
    ASSERT_TRUE(csvdiff.count(n)) << n << "\n" << out;
    EXPECT_EQ(csvdiff[n], "0.0") << n << ": mat and csv differ";
  }

  const std::pair<const char*, long> stats[] = {
      {"nsteps", tr.nsteps}, {"nfailed", tr.nfailed}, {"nfevals", tr.nfevals}};
  for (const auto& [n, expected] : stats) {
    ASSERT_TRUE(vars.count(n)) << n;
    EXPECT_EQ(vars[n].dtype, "float64") << n;
    EXPECT_EQ(vars[n].rows, 1) << n;
    EXPECT_EQ(vars[n].cols, 1) << n;
    ASSERT_EQ(vars[n].values.size(), 1u) << n;
    EXPECT_EQ(vars[n].values[0], static_cast<double>(expected)) << n;
  }
}

TEST_F(ResultWriterTest, UnwritablePathThrowsNamingThePath) {
  const Model m = makeModel();
  const Trajectory tr = makeTrajectory(m);
  const std::string bad = "/nonexistent_flexmb_dir_7f3a/run";
  auto expectThrowWith = [](auto&& f, const std::string& needle) {
    try {
      f();
      ADD_FAILURE() << "no exception; expected one naming " << needle;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectThrowWith([&] { flexmb::io::writeCsv(bad, m, tr); }, bad + "_x.csv");
  expectThrowWith([&] { flexmb::io::writeMat(bad + ".mat", m, tr); }, bad + ".mat");
  // A directory is not writable as a file, even for root.
  expectThrowWith([&] { flexmb::io::writeMat(dir_.string(), m, tr); }, dir_.string());
}

TEST_F(ResultWriterTest, NonFiniteValuesThrowNamingQuantityTimeAndColumn) {
  const Model m = makeModel();
  Trajectory tr = makeTrajectory(m);
  tr.states[2].ed[3] = std::numeric_limits<double>::quiet_NaN();
  const std::string prefix = path("nan");
  try {
    flexmb::io::writeCsv(prefix, m, tr);
    ADD_FAILURE() << "NaN written silently to CSV";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("in ed "), std::string::npos) << msg;
    EXPECT_NE(msg.find("t = 0.5333333"), std::string::npos) << msg;
    EXPECT_NE(msg.find("PLHINGE7.e1_relative_rotation"), std::string::npos) << msg;
  }
  EXPECT_FALSE(fs::exists(prefix + "_x.csv")) << "files written before the check";

  EXPECT_THROW(flexmb::io::writeMat(path("nan.mat"), m, tr), std::runtime_error);
  EXPECT_FALSE(fs::exists(path("nan.mat")));
}

TEST_F(ResultWriterTest, SizeMismatchThrows) {
  const Model m = makeModel();
  Trajectory tr = makeTrajectory(m);
  tr.states[1].sig.resize(3);
  EXPECT_THROW(flexmb::io::writeCsv(path("bad"), m, tr), std::runtime_error);
  Trajectory tr2 = makeTrajectory(m);
  tr2.time.pop_back();
  EXPECT_THROW(flexmb::io::writeMat(path("bad.mat"), m, tr2), std::runtime_error);
}

TEST_F(ResultWriterTest, EmptyTrajectoryWritesHeadersAndEmptyMatrices) {
  const Model m = makeModel();
  const Trajectory tr = makeTrajectory(m, 0);
  const auto files = flexmb::io::writeCsv(path("empty"), m, tr);
  ASSERT_EQ(files.size(), 7u);
  EXPECT_EQ(lines(readFile(files[0])).size(), 1u);
  EXPECT_NO_THROW(flexmb::io::writeMat(path("empty.mat"), m, tr));
  EXPECT_TRUE(fs::exists(path("empty.mat")));
}

// Orientation output of spatial models: an Euler-parameter node turned by a known angle about a known
// axis (lambda slightly off unit length, as after integration) gives back that rotation vector and
// the rotation matrix of Rodrigues' formula, written independently here.
TEST(ResultWriterOrientation, EulerNodeRotationVectorAndMatrix) {
  Model m;
  m.sourceFile = "spatial.dat";
  Node pos, rot;
  pos.label = 1, pos.kind = NodeKind::SpatialPosition, pos.firstCoord = 0;
  rot.label = 2, rot.kind = NodeKind::EulerParameters, rot.firstCoord = 3;
  m.nodes = {pos, rot};
  m.nodeByLabel = {{1, 0}, {2, 1}};
  m.nx = 7;
  m.xOwnerNode = {0, 0, 0, 1, 1, 1, 1};
  m.xRole.assign(7, Role::Calculable);
  m.x0 = Eigen::VectorXd::Zero(7);
  m.ne = 0;
  EXPECT_TRUE(flexmb::io::hasOrientationNodes(m));

  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  const double angles[] = {0.0, 0.7, 2.9};
  Trajectory tr;
  for (int k = 0; k < 3; ++k) {
    StateOutputs s;
    s.x = Eigen::VectorXd::Zero(7);
    s.x[3] = std::cos(angles[k] / 2) * 1.001;
    s.x.segment<3>(4) = axis * std::sin(angles[k] / 2) * 1.001;
    s.xd = s.xdd = Eigen::VectorXd::Zero(7);
    s.e = s.ed = s.edd = s.sig = Eigen::VectorXd::Zero(0);
    tr.time.push_back(0.1 * k);
    tr.states.push_back(s);
  }
  const fs::path dir = fs::temp_directory_path() / ("flexmb_rot_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = flexmb::io::writeOrientationCsv((dir / "r").string(), m, tr);
  ASSERT_EQ(path, (dir / "r_rot.csv").string());
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header,
            "time,node2.rx,node2.ry,node2.rz,node2.R11,node2.R12,node2.R13,node2.R21,node2.R22,"
            "node2.R23,node2.R31,node2.R32,node2.R33");
  for (int k = 0; k < 3; ++k) {
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    std::vector<double> v;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 13u);
    const Eigen::Matrix3d K =
        (Eigen::Matrix3d() << 0, -axis[2], axis[1], axis[2], 0, -axis[0], -axis[1], axis[0], 0).finished();
    const Eigen::Matrix3d R = Eigen::Matrix3d::Identity() + std::sin(angles[k]) * K + (1 - std::cos(angles[k])) * K * K;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[1 + c], angles[k] * axis[c], 1e-14) << "time " << k;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(v[4 + 3 * i + j], R(i, j), 1e-14) << "time " << k;
  }
  // A planar model has no orientation output.
  EXPECT_FALSE(flexmb::io::hasOrientationNodes(makeModel()));
  EXPECT_EQ(flexmb::io::writeOrientationCsv((dir / "p").string(), makeModel(), Trajectory{}), "");
  fs::remove_all(dir);
}
