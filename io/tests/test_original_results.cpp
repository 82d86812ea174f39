// A refined model's results at the original nodes and elements (io/formats/OriginalResults.hpp,
// `--refine N`): the guidance (5 PLBEAMs per leaf) refined by 2 is written with exactly the columns,
// SPACAR topology and variable sizes of the unrefined guidance, each value the refined run's at that
// coordinate or deformation; what is over the refined degrees of freedom (M0, dx) is left out; a
// table loses only the columns of new nodes and elements; io::ReadOptions::refinedResults writes
// every node.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/formats/DatReader.hpp"
#include "io/formats/OriginalResults.hpp"
#include "io/formats/ResultWriter.hpp"
#include "io/formats/SpacarResults.hpp"

using namespace flexmb;
namespace fs = std::filesystem;

namespace {
const std::string kGuidance = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/straight_guidance.dat";

core::Model guidance(int refine, bool refinedResults = false) {
  io::ReadOptions o;
  o.refine = refine;
  o.refinedResults = refinedResults;
  return io::readDatStages(kGuidance, o).back().model;
}

// Two output times; entry i of every quantity is 1000 t + i (+ 0.5 for the deformations), so a value
// says where it came from.
core::Trajectory numbered(const core::Model& m) {
  core::Trajectory t;
  for (double time : {0.0, 1.0}) {
    core::StateOutputs s;
    s.x = Eigen::VectorXd::LinSpaced(m.nx, 0, m.nx - 1).array() + 1000 * time;
    s.xd = s.xdd = s.x;
    s.e = Eigen::VectorXd::LinSpaced(m.ne, 0, m.ne - 1).array() + 1000 * time + 0.5;
    s.ed = s.edd = s.sig = s.e;
    t.time.push_back(time);
    t.states.push_back(s);
  }
  return t;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
std::string header(const std::string& csv) { return csv.substr(0, csv.find('\n')); }

class OriginalResults : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("flexmb_original_results_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  fs::path dir_;
};

const io::SpacarVariable& variable(const std::vector<io::SpacarFileContents>& files, const std::string& name) {
  for (const auto& f : files)
    for (const auto& v : f.variables)
      if (v.name == name) return v;
  throw std::runtime_error("no variable " + name);
}
bool hasVariable(const std::vector<io::SpacarFileContents>& files, const std::string& name) {
  for (const auto& f : files)
    for (const auto& v : f.variables)
      if (v.name == name) return true;
  return false;
}

// One SPACAR step of the numbered state at t = 0, with a system matrix and dx over the refined
// degrees of freedom and two mode shapes in x.
io::SpacarResults numberedSpacar(const core::Model& m) {
  const io::SpacarLayout L = io::spacarLayout(m);
  const core::StateOutputs s = numbered(m).states[0];
  io::SpacarResults r;
  r.mode = 2;
  r.time = {0.0};
  io::SpacarStep st;
  st.x = L.sortX(s.x), st.xd = L.sortX(s.xd), st.xdd = L.sortX(s.xdd), st.fxt = L.sortX(s.x);
  st.e = L.sortE(s.e), st.ed = L.sortE(s.ed), st.edd = L.sortE(s.edd), st.sig = L.sortE(s.sig);
  st.M0 = st.K0 = st.G0 = st.C0 = st.D0 = st.N0 = Eigen::MatrixXd::Identity(L.nddof(), L.nddof());
  st.dx = Eigen::MatrixXd::Ones(m.nx, L.ndof());
  st.freq = Eigen::Vector2d(5.0, 7.0);
  st.modeq = Eigen::MatrixXd::Ones(L.nddof(), 2);
  st.modex.resize(m.nx, 2);
  st.modex.col(0) = st.x;
  st.modex.col(1) = 2 * st.x;
  r.steps.push_back(st);
  return r;
}
}  // namespace

TEST_F(OriginalResults, CsvHasTheOriginalColumnsWithTheRefinedValues) {
  const core::Model plain = guidance(1), fine = guidance(2);
  ASSERT_TRUE(fine.unrefined);
  ASSERT_FALSE(plain.unrefined);
  ASSERT_GT(fine.nx, plain.nx);
  ASSERT_GT(fine.ne, plain.ne);
  EXPECT_EQ(&io::resultModel(plain), &plain);
  EXPECT_EQ(io::resultModel(fine).nx, plain.nx);
  io::writeCsv((dir_ / "plain").string(), plain, numbered(plain));
  io::writeCsv((dir_ / "fine").string(), fine, numbered(fine));
  for (const char* q : {"_x", "_xd", "_xdd", "_e", "_ed", "_edd", "_sig"}) {
    // numbered() of the refined model at the original entries is numbered() of the original: the
    // files are the same bytes when the values are those of the refined run at the original places.
    EXPECT_EQ(slurp(dir_ / ("fine" + std::string(q) + ".csv")), slurp(dir_ / ("plain" + std::string(q) + ".csv"))) << q;
  }
  // The refined model's own files: every coordinate, the original ones first.
  const core::Model all = guidance(2, true);
  EXPECT_FALSE(all.unrefined);
  io::writeCsv((dir_ / "all").string(), all, numbered(all));
  const std::string hx = header(slurp(dir_ / "all_x.csv")), px = header(slurp(dir_ / "plain_x.csv"));
  EXPECT_EQ(hx.rfind(px + ",", 0), 0u) << hx;
  EXPECT_GT(hx.size(), px.size() + 10);
}

TEST_F(OriginalResults, SpacarFilesHaveTheOriginalLayout) {
  const core::Model plain = guidance(1), fine = guidance(2);
  const auto p = io::spacarResultFiles("p", plain, numberedSpacar(plain));
  const auto f = io::spacarResultFiles("f", fine, numberedSpacar(fine));
  // The topology and the state as the unrefined file's: numbered() values at the original places.
  for (const char* name :
       {"lnp", "ln", "le", "nxp", "nep", "x", "xd", "xdd", "e", "ed", "edd", "sig", "fxt", "modex", "freq"}) {
    const io::SpacarVariable &a = variable(p, name), &b = variable(f, name);
    EXPECT_EQ(a.dims, b.dims) << name;
    EXPECT_EQ(a.data, b.data) << name;
  }
  // Over the refined degrees of freedom: left out.
  for (const char* name : {"M0", "K0", "dx", "modeq"}) {
    EXPECT_TRUE(hasVariable(p, name)) << name;
    EXPECT_FALSE(hasVariable(f, name)) << name;
  }
  // --refined-results: the refined model's layout, more coordinates, its matrices.
  const core::Model all = guidance(2, true);
  const auto a = io::spacarResultFiles("a", all, numberedSpacar(all));
  EXPECT_EQ(variable(a, "x").dims.at(1), static_cast<std::size_t>(all.nx));
  EXPECT_GT(all.nx, plain.nx);
  EXPECT_TRUE(hasVariable(a, "M0"));
}

TEST_F(OriginalResults, TablesLoseOnlyTheNewNodesAndElements) {
  const core::Model fine = guidance(2);
  const core::Model& plain = io::resultModel(fine);
  io::CsvTable t;
  const auto x = io::coordinateColumnNames(fine), e = io::deformationColumnNames(fine);
  t.columns = {"time",
               x[0],
               "F." + x[1],
               "x:" + x[plain.nx - 1],
               x[plain.nx],
               "F." + x.back(),
               "xd:" + x.back(),
               e[0],
               "sig:" + e[plain.ne],
               "max_stress"};
  const core::ElementEntry& last = fine.elements.back();
  const core::ElementEntry& first = fine.elements.front();
  t.columns.push_back("stress_" + last.type->keyword + std::to_string(last.label));
  t.columns.push_back("stress_" + first.type->keyword + std::to_string(first.label));
  std::vector<double> row;
  for (std::size_t c = 0; c < t.columns.size(); ++c) row.push_back(static_cast<double>(c));
  t.rows = {row, row};
  const io::CsvTable o = io::originalColumns(fine, t);
  const std::vector<std::string> kept = {"time", x[0],         "F." + x[1],     "x:" + x[plain.nx - 1],
                                         e[0],   "max_stress", t.columns.back()};
  EXPECT_EQ(o.columns, kept);
  ASSERT_EQ(o.rows.size(), 2u);
  EXPECT_EQ(o.rows[1], (std::vector<double>{0, 1, 2, 3, 7, 9, 11}));
  // Not refined: as it is.
  EXPECT_EQ(io::originalColumns(plain, t).columns, t.columns);
}
