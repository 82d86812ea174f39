// `flexmb study --accuracy EPS` and `--error-estimate` (analysis/StudyAccuracy.hpp): the mesh chosen
// at the range's two ends is the one a single run chooses for the nominal design, every variant's
// error columns are there and meet EPS, and the true error of each variant against a closed form
// (Euler-Bernoulli) or a much finer mesh (--refine 16) is within EPS.
#include <cmath>
#include <map>
#include <regex>

#include "io/templates/StudySummary.hpp"
#include "tools/tests/CliFixture.hpp"

using namespace flexmb::cli_test;

namespace {

class StudyAccuracyCli : public CliTest {
 protected:
  std::vector<flexmb::io::StudyRecord> summary(const std::string& folder) {
    const fs::path p = dir_ / folder / "study_summary.csv";
    return flexmb::io::parseStudyTable(slurp(p), p.string());
  }
};

double quantityOf(const flexmb::io::StudyRecord& r, const std::string& name) {
  for (const auto& [n, v] : r.quantities)
    if (n == name) return v;
  ADD_FAILURE() << "no column " << name << " in variant " << r.name;
  return std::nan("");
}

// The number after `key` in text (-1: not there).
int numberAfter(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  return at == std::string::npos ? -1 : std::atoi(text.c_str() + at + key.size());
}

// Every variant has the error columns, finite, within EPS and marked met.
void expectMet(const std::vector<flexmb::io::StudyRecord>& rows, double eps) {
  ASSERT_FALSE(rows.empty());
  for (const auto& r : rows) {
    EXPECT_EQ(r.status, "ok") << r.name << ": " << r.reason;
    for (const char* c : {"discretization_error", "integration_error", "reduction_error", "total_error_estimate"})
      EXPECT_TRUE(std::isfinite(quantityOf(r, c))) << r.name << " " << c;
    EXPECT_GT(quantityOf(r, "discretization_error"), 0.0) << r.name;
    EXPECT_LE(quantityOf(r, "total_error_estimate"), eps) << r.name;
    EXPECT_EQ(quantityOf(r, "accuracy_met"), 1.0) << r.name;
  }
}

// The static table's last equilibrium and its first (the unloaded configuration): the position
// columns (node<n>.x, .y) by name.
struct Positions {
  std::vector<std::string> names;
  std::vector<double> first, last;
};
Positions staticPositions(const std::string& csv) {
  std::istringstream in(csv);
  std::string header, line, first, last;
  std::getline(in, header);
  std::getline(in, first);
  last = first;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  auto cells = [](const std::string& l) {
    std::vector<std::string> out;
    std::stringstream s(l);
    for (std::string c; std::getline(s, c, ',');) out.push_back(c);
    return out;
  };
  const auto h = cells(header), a = cells(first), b = cells(last);
  Positions p;
  const std::regex position("node[0-9]+\\.[xyz]");
  for (size_t i = 0; i < h.size() && i < a.size() && i < b.size(); ++i)
    if (std::regex_match(h[i], position)) {
      p.names.push_back(h[i]);
      p.first.push_back(std::stod(a[i]));
      p.last.push_back(std::stod(b[i]));
    }
  return p;
}

// The node<n>.x/.y columns of a time table (`#` lines skipped), by name: one vector per column.
std::map<std::string, std::vector<double>> timePositions(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::vector<std::string> header;
  std::map<std::string, std::vector<double>> out;
  const std::regex position("node[0-9]+\\.[xy]");
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream cs(line);
    for (std::string c; std::getline(cs, c, ',');) cells.push_back(c);
    if (header.empty()) {
      header = cells;
      continue;
    }
    for (size_t i = 0; i < header.size() && i < cells.size(); ++i)
      if (std::regex_match(header[i], position)) out[header[i]].push_back(std::stod(cells[i]));
  }
  return out;
}

// The guidance pushed by F (the shipped file has F = 100): the study's mesh is at least the one
// `simulate --accuracy` chooses for the nominal design, and the nominal's own ladder chose exactly
// that.
TEST_F(StudyAccuracyCli, GuidanceSimulateChoosesTheSingleRunsMeshForTheNominal) {
  variant("straight_guidance.dat", "\\? 50\\*\\(1-cos", "? {F/2}*(1-cos", "guidance.dat");
  const Result one =
      flexmb("simulate " + kData + "straight_guidance.dat --accuracy 1e-2 --format csv --out one --quiet");
  ASSERT_EQ(one.code, 0) << one.err;
  const int single = numberAfter(slurp(dir_ / "one_run.txt"), "\nrefinement chosen: ");
  ASSERT_GT(single, 0);
  const Result r = flexmb("study guidance.dat --param F=100,140 --simulate --accuracy 1e-2 --jobs 2 --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "v0001: simulate at refine 1")) << r.err;  // the ladder's levels, as they come
  EXPECT_TRUE(has(r.out, "study mesh: refine ")) << r.out;
  const std::string study = slurp(dir_ / "s" / "study.txt");
  EXPECT_EQ(numberAfter(study, "(the larger of v0001 "), single) << study;
  EXPECT_GE(numberAfter(study, "\nrefinement chosen: "), single) << study;
  for (const char* key :
       {"\naccuracy target: 0.01 of the motion", "\nintegrator tolerance: RelTol 0.0005",
        "\ndiscretization measured: by simulate at the parameter range's ends (v0001 and v0002)",
        "\ndiscretization ladder: v0001: ", "\ndiscretization ladder: v0002: ", "\naccuracy reachable: yes"})
    EXPECT_TRUE(has(study, key)) << key << "\n" << study;
  EXPECT_TRUE(has(slurp(dir_ / "s" / "study_run.txt"), "\nrefinement chosen: ")) << "collect repeats it";
  const auto rows = summary("s");
  expectMet(rows, 1e-2);
  // The nominal (F = 100 N, the shipped file's load) against the guidance's converged answer
  // computed independently (validation/references: 40 and 80 elements a leaf, extrapolated).
  const auto truth = timePositions(slurp(kSource + "/validation/references/straight_guidance_converged.csv"));
  const auto run = timePositions(slurp(dir_ / "s" / "variants" / "v0001" / "guidance_x.csv"));
  ASSERT_FALSE(truth.empty());
  double motion = 0.0, error = 0.0;
  for (const auto& [name, values] : truth) {
    ASSERT_TRUE(run.count(name)) << name;
    ASSERT_EQ(run.at(name).size(), values.size()) << name;
    for (size_t k = 0; k < values.size(); ++k) {
      motion = std::max(motion, std::abs(values[k] - values[0]));
      error = std::max(error, std::abs(run.at(name)[k] - values[k]));
    }
  }
  EXPECT_LE(error / motion, 1e-2);                                              // measured 3.9e-3
  EXPECT_GE(quantityOf(rows.front(), "total_error_estimate"), error / motion);  // the estimate is above it
  for (const auto& row : rows) {
    EXPECT_GT(quantityOf(row, "integration_error"), 0.0) << row.name;      // the accuracy check ran
    EXPECT_EQ(quantityOf(row, "reduction_error"), 0.0) << row.name;        // the full model
    EXPECT_EQ(quantityOf(row, "dofs"), quantityOf(rows.front(), "dofs"));  // one mesh for all
  }
}

// The cantilever under a tip load P that bends it far (P L^2 / EI up to 2): the mesh chosen meets
// EPS in every variant's tip path against a run 16 times finer.
TEST_F(StudyAccuracyCli, StaticStudyIsWithinEpsOfAMuchFinerMesh) {
  variant("cantilever.dat", "DELXF 5  0.0  -0.1", "DELXF 5  0.0  {-P}", "cantilever.dat");
  const double eps = 1e-3;
  const Result r = flexmb("study cantilever.dat --param P=2,3.5,5.6 --static --accuracy 1e-3 --jobs 2 --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = summary("s");
  expectMet(rows, eps);
  for (const auto& row : rows) EXPECT_EQ(quantityOf(row, "integration_error"), 0.0);
  // The nominal's mesh: as `static --accuracy` chooses for it.
  const Result one = flexmb("static s/variants/v0001/cantilever.dat --accuracy 1e-3 --out one.csv --quiet");
  ASSERT_EQ(one.code, 0) << one.err;
  const std::string study = slurp(dir_ / "s" / "study.txt");
  EXPECT_EQ(numberAfter(study, "(the larger of v0001 "),
            numberAfter(slurp(dir_ / "one_run.txt"), "\nrefinement chosen: "))
      << study;
  const Result fine = flexmb("study cantilever.dat --param P=2,3.5,5.6 --static --refine 16 --jobs 2 --out f --quiet");
  ASSERT_EQ(fine.code, 0) << fine.err;
  for (const char* v : {"v0001", "v0002", "v0003"}) {
    const Positions a = staticPositions(slurp(dir_ / "s" / "variants" / v / "cantilever_static.csv"));
    const Positions b = staticPositions(slurp(dir_ / "f" / "variants" / v / "cantilever_static.csv"));
    ASSERT_EQ(a.names, b.names);
    ASSERT_FALSE(a.names.empty());
    double motion = 0.0, error = 0.0;
    for (size_t i = 0; i < a.names.size(); ++i) {
      motion = std::max(motion, std::abs(b.last[i] - b.first[i]));
      error = std::max(error, std::abs(a.last[i] - b.last[i]));
    }
    ASSERT_GT(motion, 0.1);  // the load bends it far: not a linear problem
    EXPECT_LE(error / motion, eps) << v;
    EXPECT_GT(error / motion, 1e-6) << v << ": the mesh did make a difference";
  }
}

// Frequencies of cantilevers of two stiffnesses against Euler-Bernoulli's closed form.
TEST_F(StudyAccuracyCli, ModesStudyIsWithinEpsOfEulerBernoulli) {
  variant("cantilever.dat", "8.4e6  2.8", "8.4e6  {EI}", "cantilever.dat");
  const double eps = 1e-3;
  const Result r = flexmb("study cantilever.dat --param EI=1.4,2.8,5.6 --modes --nev 4 --accuracy 1e-3 --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = summary("s");
  expectMet(rows, eps);
  const double betaL[] = {1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349};
  const double rhoA = 0.312, L = 1.0;
  for (const auto& row : rows) {
    const double EI = row.parameters.at(0).second;
    for (int i = 0; i < 4; ++i) {
      const double exact = betaL[i] * betaL[i] * std::sqrt(EI / (rhoA * std::pow(L, 4))) / (2 * M_PI);
      std::string column = "f";  // piecewise: GCC 12's -Wrestrict on "f" + std::string
      column += std::to_string(i + 1);
      column += "_Hz";
      const double f = quantityOf(row, column);
      EXPECT_LE(std::abs(f / exact - 1.0), eps) << row.name << " mode " << i + 1;
    }
  }
  // The model's own mesh (4 elements) misses EPS on its fourth mode: the study refined it.
  EXPECT_GT(numberAfter(slurp(dir_ / "s" / "study.txt"), "\nrefinement chosen: "), 1);
}

// --reduce: the mesh gets half of EPS, each variant's basis a quarter; a reduced variant's
// reduction error is its basis' estimate, a variant no basis served ran the full model (0).
TEST_F(StudyAccuracyCli, ReduceSplitsTheTarget) {
  variant("straight_guidance.dat", "\\? 50\\*\\(1-cos", "? {F/2}*(1-cos", "guidance.dat");
  const Result r = flexmb("study guidance.dat --param F=60,140 --simulate --accuracy 1e-2 --reduce --jobs 2 --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string study = slurp(dir_ / "s" / "study.txt");
  EXPECT_TRUE(has(study, "\nreduction target: 0.0025 (a quarter of the accuracy target)")) << study;
  EXPECT_TRUE(has(study, "\nintegrator tolerance: RelTol 0.0005")) << study;
  const auto rows = summary("s");
  expectMet(rows, 1e-2);
  for (const auto& row : rows) {
    const double vectors = quantityOf(row, "sim_basis_vectors"), reduction = quantityOf(row, "reduction_error");
    if (std::isnan(vectors))
      EXPECT_EQ(reduction, 0.0) << row.name;
    else
      EXPECT_EQ(reduction, quantityOf(row, "sim_reduction_estimate")) << row.name;
    EXPECT_LE(reduction, 0.25 * 1e-2) << row.name;
    EXPECT_LE(quantityOf(row, "discretization_error"), 0.5 * 1e-2) << row.name;
  }
}

// A study of several analyses ladders each: the mesh is the largest any of them chose, and the
// frequencies meet EPS though the static ladder alone would choose a coarser mesh.
TEST_F(StudyAccuracyCli, EveryAnalysisIsLadderedAndTheFinestMeshWins) {
  variant("cantilever.dat", "8.4e6  2.8", "8.4e6  {EI}", "cantilever.dat");
  const Result r = flexmb("study cantilever.dat --param EI=2.8,5.6 --static --modes --nev 4 --accuracy 1e-3 --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string study = slurp(dir_ / "s" / "study.txt");
  EXPECT_TRUE(has(study, "by static and modes at the parameter range's ends (v0001 and v0002)")) << study;
  const int chosen = numberAfter(study, "\nrefinement chosen: ");
  for (const char* ladder : {"v0001 static ", "v0002 static ", "v0001 modes ", "v0002 modes "}) {
    const int n = numberAfter(study, ladder);
    EXPECT_GT(n, 0) << ladder;
    EXPECT_LE(n, chosen) << ladder;
  }
  expectMet(summary("s"), 1e-3);
}

// --error-estimate: the model's own mesh runs, its estimate from the two ends; no target to meet.
TEST_F(StudyAccuracyCli, ErrorEstimateKeepsTheModelsMesh) {
  variant("cantilever.dat", "DELXF 5  0.0  -0.1", "DELXF 5  0.0  {-P}", "cantilever.dat");
  const Result r = flexmb("study cantilever.dat --param P=0.1,2 --static --error-estimate --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string study = slurp(dir_ / "s" / "study.txt");
  EXPECT_EQ(numberAfter(study, "\nrefinement chosen: "), 1) << study;
  EXPECT_TRUE(has(study, "\naccuracy target: none")) << study;
  for (const auto& row : summary("s")) {
    EXPECT_GT(quantityOf(row, "discretization_error"), 1e-4) << row.name;  // 4 elements: not converged
    EXPECT_TRUE(std::isnan(quantityOf(row, "accuracy_met"))) << row.name;  // an empty cell
  }
  // Resumed: the ladders measure the same, so the finished variants are skipped.
  const Result again = flexmb("study cantilever.dat --param P=0.1,2 --static --error-estimate --out s");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(has(again.out, "2 finished before (skipped), 0 to run")) << again.out;
}

// A target the time allowed cannot reach is said before the variants run; they run on the finest
// mesh reached and are marked accuracy_met 0.
TEST_F(StudyAccuracyCli, UnreachableTargetIsSaidBeforeTheVariants) {
  variant("straight_guidance.dat", "\\? 50\\*\\(1-cos", "? {F/2}*(1-cos", "guidance.dat");
  const Result r =
      flexmb("study guidance.dat --param F=100 --simulate --accuracy 1e-4 --max-seconds 0.3 --jobs 1 --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "cannot be reached")) << r.err;
  EXPECT_TRUE(has(slurp(dir_ / "s" / "study.txt"), "\naccuracy reachable: no"));
  for (const auto& row : summary("s")) EXPECT_EQ(quantityOf(row, "accuracy_met"), 0.0) << row.name;
}

TEST_F(StudyAccuracyCli, ClashesAreUsageErrors) {
  variant("straight_guidance.dat", "\\? 50\\*\\(1-cos", "? {F/2}*(1-cos", "guidance.dat");
  const std::string s = "study guidance.dat --param F=100 --simulate ";
  EXPECT_EQ(flexmb(s + "--reduce").code, 2);                                              // --reduce splits an EPS
  EXPECT_EQ(flexmb(s + "--accuracy 1e-2 --target 1e-3").code, 2);                         // --accuracy sets the target
  EXPECT_EQ(flexmb(s + "--accuracy 1e-2 --error-estimate").code, 2);                      // one or the other
  EXPECT_EQ(flexmb(s + "--accuracy 1e-2 --slurm --dry-run").code, 2);                     // not on a login node
  EXPECT_EQ(flexmb("study guidance.dat --param F=100 --check --accuracy 1e-2").code, 2);  // nothing to ladder
}

}  // namespace
