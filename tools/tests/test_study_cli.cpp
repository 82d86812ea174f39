// `flexmb study` as a user meets it (issue 26): a study of the shipped cross-spring pivot template
// with the leaf thickness as parameter run with --jobs 1 and --jobs 2 (identical tables), split into
// tasks (the same union), interrupted with SIGINT or killed and resumed (only the missing variants
// run), failing variants recorded with their reason while the others succeed, a crashed worker
// recorded and the study going on, the summary's frequencies against `flexmb modes` on the
// instantiated model, the Slurm scripts run by hand, and the errors that stop a study before it runs.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "io/templates/StudyTable.hpp"
#include "tools/tests/CliFixture.hpp"

namespace fs = std::filesystem;

namespace {

using namespace flexmb::cli_test;

const std::string kPivot = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_study.dat";

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> v;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

// The study's scripts keep their out.txt / err.txt beside the study.
Result runIn(const fs::path& dir, const std::string& script) { return runScript(dir, script, false); }

int countManifests(const fs::path& study) {
  int n = 0;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(study / "variants", ec))
    if (e.path().filename().string().ends_with("_run.txt")) ++n;
  return n;
}

class StudyCli : public CliTest {
 protected:
  StudyCli() : CliTest("flexmb_study_") {}
  Result run(const std::string& script) { return runIn(dir_, script); }
  // The reference: 6 variants of the pivot, static with buckling and modes, --jobs 2 (made once).
  static std::string referenceTable() {
    static std::string table;
    if (table.empty()) {
      const fs::path d = fs::temp_directory_path() / ("flexmb_study_reference_" + std::to_string(::getpid()));
      fs::remove_all(d);
      fs::create_directories(d);
      const Result r = runIn(d, "flexmb study " + kPivot + " " + kArgs + " --jobs 2 --out ref");
      EXPECT_EQ(r.code, 0) << r.err;
      table = slurp(d / "ref" / "study_summary.csv");
      fs::remove_all(d);
    }
    return table;
  }
  static inline const std::string kArgs = "--param t=0.1e-3:0.5e-3:6 --static --buckling --modes -q";
};

}  // namespace

TEST_F(StudyCli, JobsOneAndTwoGiveIdenticalTables) {
  const Result r = run("flexmb study " + kPivot + " " + kArgs + " --jobs 1 --out one");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string one = slurp(dir_ / "one" / "study_summary.csv");
  const std::string two = referenceTable();
  EXPECT_EQ(one, two);
  const auto rows = lines(one);
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_EQ(rows[0].rfind("variant,name,t,status,dofs,f1_Hz,", 0), 0u) << rows[0];
  for (size_t i = 1; i < rows.size(); ++i) EXPECT_NE(rows[i].find(",ok,"), std::string::npos) << rows[i];
  EXPECT_NE(rows[1].find("v0001,0.0001,ok"), std::string::npos) << rows[1];
  EXPECT_NE(rows[6].find("v0006,0.0005,ok"), std::string::npos) << rows[6];
  // Each variant's folder: the instantiated model, its summary, the analyses' tables and the
  // manifest (written last) naming the files and the fingerprint.
  const fs::path v = dir_ / "one" / "variants" / "v0003";
  for (const char* f : {".dat", "_summary.csv", "_static.csv", "_modes.csv", "_run.txt"})
    EXPECT_TRUE(fs::exists(v / ("cross_spring_pivot_study" + std::string(f)))) << f;
  const std::string manifest = slurp(v / "cross_spring_pivot_study_run.txt");
  EXPECT_NE(manifest.find("status: complete"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("fingerprint: "), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("file: cross_spring_pivot_study_summary.csv"), std::string::npos) << manifest;
  // EA = E w t of v0003 (t = 0.00026) as the model holds it.
  const std::string model = slurp(v / "cross_spring_pivot_study.dat");
  const std::string estiff = "ESTIFF\t\t  1\t";
  const auto ea = model.find(estiff);
  ASSERT_NE(ea, std::string::npos);
  EXPECT_NEAR(std::stod(model.substr(ea + estiff.size())) / (210e9 * 0.05 * 0.00026), 1.0, 1e-15);
  // The report: a plot of the first frequency against the leaf thickness, inline and as SVG.
  const std::string html = slurp(dir_ / "one" / "study_report.html");
  EXPECT_NE(html.find("f1_Hz against t"), std::string::npos);
  EXPECT_NE(html.find("6 variants: 6 ok, 0 failed, 0 not run yet"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir_ / "one" / "study_f1_Hz_vs_t.svg"));
  EXPECT_NE(slurp(dir_ / "one" / "study_run.txt").find("status: complete"), std::string::npos);
  // The first frequency rises with the thickness (f ~ t^1.5 for leaves in bending).
  double last = 0;
  for (size_t i = 1; i < rows.size(); ++i) {
    const double f1 = std::stod(rows[i].substr(rows[i].find(",ok,30,") + 7));
    EXPECT_GT(f1, last);
    last = f1;
  }
  // Running it again changes nothing: every variant is finished.
  const Result again = run("flexmb study " + kPivot +
                           " --param t=0.1e-3:0.5e-3:6 --static --buckling --modes "
                           "--jobs 1 --out one");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("6 finished before (skipped), 0 to run"), std::string::npos) << again.out;
  EXPECT_EQ(slurp(dir_ / "one" / "study_summary.csv"), one);
}

TEST_F(StudyCli, TaskSplitsGiveTheSameUnion) {
  // Three tasks, two of them at once, in one folder; then collect.
  const Result r =
      run("flexmb study " + kPivot + " " + kArgs + " --jobs 1 --out s --task 2 --of 3 & " + "flexmb study " + kPivot +
          " " + kArgs + " --jobs 1 --out s --task 0 --of 3; wait $! && " + "flexmb study " + kPivot + " " + kArgs +
          " --out s --task 1 --of 3 && " + "flexmb study collect s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(dir_ / "s" / "study_summary.csv"), referenceTable());
  // A partial collect says what is missing.
  const Result p = run("flexmb study " + kPivot + " " + kArgs + " --out p --task 0 --of 2 && flexmb study collect p");
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_NE(p.out.find("6 variants, 3 not run yet"), std::string::npos) << p.out;
  const std::string partial = slurp(dir_ / "p" / "study_summary.csv");
  EXPECT_NE(partial.find("2,v0002,0.00018,missing"), std::string::npos) << partial;
  EXPECT_NE(slurp(dir_ / "p" / "study_run.txt").find("status: incomplete: 3 variants not run yet"), std::string::npos);
}

TEST_F(StudyCli, InterruptAndResumeRunOnlyTheMissingVariants) {
  // 40 variants one at a time; Ctrl-C (SIGINT to the study) once a few have finished.
  const std::string args = "--param t=0.1e-3:0.5e-3:40 --static";
  const Result r = run("flexmb study " + kPivot + " " + args +
                       " --jobs 1 --out s -q & pid=$!\n"
                       "for i in $(seq 600); do [ $(ls s/variants/*/*_run.txt 2>/dev/null | wc -l) -ge 3 ] && break; "
                       "sleep 0.05; done\n"
                       "kill -INT $pid; wait $pid; echo rc=$?");
  EXPECT_NE(r.out.find("rc=130"), std::string::npos) << r.out << r.err;
  const int finished = countManifests(dir_ / "s");
  ASSERT_GE(finished, 3);
  ASSERT_LT(finished, 40) << "the study ended before the interrupt: make it longer";
  EXPECT_NE(
      r.err.find("interrupted: " + std::to_string(finished) + " of 40 variants finished; the same command resumes"),
      std::string::npos)
      << r.err;
  // The partial table and report: the finished variants, the others missing, the set incomplete.
  const std::string partial = slurp(dir_ / "s" / "study_summary.csv");
  EXPECT_NE(partial.find(",missing"), std::string::npos) << partial;
  EXPECT_NE(slurp(dir_ / "s" / "study_run.txt")
                .find("status: incomplete: " + std::to_string(40 - finished) + " variants not run yet"),
            std::string::npos);
  // No worker is left, and nothing half-written under a final name: every variant folder with a
  // summary has its manifest.
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "s" / "variants", ec))
    if (e.path().filename().string().ends_with("_summary.csv")) {
      const std::string m = e.path().string().substr(0, e.path().string().size() - 12) + "_run.txt";
      EXPECT_TRUE(fs::exists(m)) << m;
    }
  // Resume: only the missing variants run.
  const auto before = fs::last_write_time(dir_ / "s" / "variants" / "v0001" / "cross_spring_pivot_study_run.txt");
  const Result again = run("flexmb study " + kPivot + " " + args + " --jobs 2 --out s");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find(std::to_string(finished) + " finished before (skipped), " + std::to_string(40 - finished) +
                           " to run"),
            std::string::npos)
      << again.out;
  EXPECT_NE(again.out.find("ran " + std::to_string(40 - finished) + " variants"), std::string::npos) << again.out;
  EXPECT_EQ(fs::last_write_time(dir_ / "s" / "variants" / "v0001" / "cross_spring_pivot_study_run.txt"), before);
  EXPECT_EQ(countManifests(dir_ / "s"), 40);
  // The resumed table is the table of an uninterrupted run.
  const Result whole = run("flexmb study " + kPivot + " " + args + " --jobs 2 -q --out w");
  ASSERT_EQ(whole.code, 0) << whole.err;
  EXPECT_EQ(slurp(dir_ / "s" / "study_summary.csv"), slurp(dir_ / "w" / "study_summary.csv"));
}

TEST_F(StudyCli, AKilledStudyResumes) {
  // SIGKILL of the study and its workers (a killed job, a crash of the machine's session): no
  // manifest for the variants in flight; their temporaries are cleaned up when they run again.
  const std::string args = "--param t=0.1e-3:0.5e-3:30 --static --jobs 2 --out s";
  const Result r = run("setsid " + kFlexmb + " study " + kPivot + " " + args +
                       " -q & pid=$!\n"
                       "for i in $(seq 600); do [ $(ls s/variants/*/*_run.txt 2>/dev/null | wc -l) -ge 4 ] && break; "
                       "sleep 0.05; done\n"
                       "kill -KILL -- -$pid; wait $pid; echo rc=$?");
  EXPECT_NE(r.out.find("rc=137"), std::string::npos) << r.out << r.err;
  const int finished = countManifests(dir_ / "s");
  ASSERT_LT(finished, 30);
  const Result again = run("flexmb study " + kPivot + " " + args);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("ran " + std::to_string(30 - finished) + " variants"), std::string::npos) << again.out;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "s", ec))
    EXPECT_EQ(e.path().filename().string().find(".part-"), std::string::npos) << e.path();
}

TEST_F(StudyCli, FailingVariantsAreRecordedWithTheirReason) {
  // t = 0 makes the template's shear flexibility 0/0; t < 0 a negative mass, which the reader
  // rejects at the template's line; the others run.
  std::ofstream(dir_ / "t.csv") << "name,t\nthin,1e-4\nzero,0\nnegative,-2e-4\nthick,3e-4\n";
  const Result r = run("flexmb study " + kPivot + " --table t.csv --static --modes --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("zero (t = 0) failed:"), std::string::npos) << r.err;
  const auto rows = lines(slurp(dir_ / "s" / "study_summary.csv"));
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_NE(rows[1].find("1,thin,0.0001,ok,"), std::string::npos) << rows[1];
  EXPECT_NE(rows[4].find("4,thick,0.0003,ok,"), std::string::npos) << rows[4];
  const std::regex zero(
      "2,zero,0,failed,.*cross_spring_pivot_study\\.dat:1[0-9]: \\{cy = EIy/\\(k\\*G\\*A\\)\\} gives "
      "NaN at t = 0");
  EXPECT_TRUE(std::regex_search(rows[2], zero)) << rows[2];
  const std::regex negative(
      "3,negative,-0.0002,failed,.*variants/negative/cross_spring_pivot_study\\.dat:6[0-9]: EM: negative mass");
  EXPECT_TRUE(std::regex_search(rows[3], negative)) << rows[3];
  EXPECT_NE(slurp(dir_ / "s" / "study_report.html").find("4 variants: 2 ok, 2 failed"), std::string::npos);
  const std::string manifest = slurp(dir_ / "s" / "variants" / "zero" / "cross_spring_pivot_study_run.txt");
  EXPECT_NE(manifest.find("status: failed: "), std::string::npos) << manifest;
  // Failed variants count as finished; --rerun-failed runs them (and only them) again.
  const Result again = run("flexmb study " + kPivot + " --table t.csv --static --modes --out s --rerun-failed");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("2 finished before (skipped), 2 to run"), std::string::npos) << again.out;
}

TEST_F(StudyCli, ACrashedWorkerIsRecordedAndTheStudyGoesOn) {
  // The cantilever with its end time as parameter: variant 1 integrates long enough to be caught
  // running; SIGSEGV to its worker stands for a crash in the analysis. Under AddressSanitizer
  // (tools/sanitize.sh) the worker must die of that signal too: handle_segv=0 keeps ASan from catching
  // the SIGSEGV sent from outside and turning it into its own report and an abort (signal 6).
  std::string model = slurp(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/cantilever.dat");
  model = std::regex_replace(model, std::regex("TIMESTEP 1.0 100"), "TIMESTEP {T} 100");
  model = std::regex_replace(model, std::regex("DELXF 5  0.0  -0.1"), "XF 5 0.0 -0.1");
  std::ofstream(dir_ / "c.dat") << model;
  const Result r =
      run("export ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}handle_segv=0\"\n"
          "flexmb study c.dat --param T=1000,0.01,0.02 --simulate --integrator ode45 --jobs 1 --out s -q & pid=$!\n"
          "for i in $(seq 400); do w=$(pgrep -P $pid); [ -n \"$w\" ] && break; sleep 0.05; done\n"
          "sleep 0.5; kill -SEGV $w; wait $pid; echo rc=$?");
  EXPECT_NE(r.out.find("rc=0"), std::string::npos) << r.out << r.err;
  EXPECT_NE(r.err.find("v0001 (T = 1000) crashed (signal 11"), std::string::npos) << r.err;
  const auto rows = lines(slurp(dir_ / "s" / "study_summary.csv"));
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_NE(rows[1].find("failed,"), std::string::npos) << rows[1];
  EXPECT_NE(rows[1].find("the analysis crashed (signal 11: Segmentation fault)"), std::string::npos) << rows[1];
  EXPECT_NE(rows[2].find(",ok,"), std::string::npos) << rows[2];
  EXPECT_NE(rows[3].find(",ok,"), std::string::npos) << rows[3];
}

TEST_F(StudyCli, SummaryFrequenciesEqualFlexmbModesOnTheInstantiatedModel) {
  const Result r = run("flexmb study " + kPivot +
                       " --param t=1.7e-4,3.3e-4 --modes -q --out s && cd "
                       "s/variants/v0002 && flexmb modes cross_spring_pivot_study.dat --out m");
  ASSERT_EQ(r.code, 0) << r.err;
  // flexmb modes prints "  mode   f [Hz] ..." rows with 8 significant digits (the first such block:
  // the effective masses' rows follow).
  std::vector<double> printed;
  const std::regex row("^ +([0-9]+) +([-0-9.e+]+) +[-0-9.e+]+");
  for (const auto& l : lines(r.out)) {
    std::smatch m;
    if (std::regex_search(l, m, row))
      printed.push_back(std::stod(m[2]));
    else if (!printed.empty())
      break;
  }
  ASSERT_EQ(printed.size(), 6u) << r.out;
  const auto rows = lines(slurp(dir_ / "s" / "study_summary.csv"));
  ASSERT_EQ(rows.size(), 3u);
  std::vector<std::string> header, cells;
  std::stringstream h(rows[0]), c(rows[2]);
  for (std::string x; std::getline(h, x, ',');) header.push_back(x);
  for (std::string x; std::getline(c, x, ',');) cells.push_back(x);
  for (int i = 0; i < 6; ++i) {
    const std::string name = std::string("f").append(std::to_string(i + 1)).append("_Hz");
    const auto at = std::find(header.begin(), header.end(), name) - header.begin();
    ASSERT_LT(static_cast<size_t>(at), cells.size());
    EXPECT_NEAR(std::stod(cells[at]) / printed[i], 1.0, 1e-7) << i;
  }
}

TEST_F(StudyCli, ErrorsStopTheStudyBeforeItRuns) {
  std::ofstream(dir_ / "m.dat") << "X 1 0 0\nX 2 {L} 0\nPLBEAM 1 1 101 2 102\n";
  Result r = run("flexmb study m.dat --param LL=1:2:3");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("m.dat:2: unknown parameter 'L' in {L} (the study's parameters: LL; did you mean 'LL'?)"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "m_study"));
  r = run("flexmb study m.dat --param L=1:2:3 --param w=1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("the parameter 'w' is not used by the template"), std::string::npos) << r.err;
  r = run("flexmb study m.dat --param L=1:2");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--param L=1:2: a range is from:to:count"), std::string::npos) << r.err;
  r = run("flexmb study m.dat");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no parameters"), std::string::npos) << r.err;
  r = run("flexmb study m.dat --param L=1 --task 1");
  EXPECT_EQ(r.code, 2);
  r = run("flexmb study m.dat --param L=1 --task 2 --of 2");
  EXPECT_EQ(r.code, 2);
  r = run("flexmb study m.dat --table missing.csv");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("missing.csv: cannot read"), std::string::npos) << r.err;
  r = run("flexmb study nothere.dat --param L=1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("nothere.dat: cannot read the template"), std::string::npos) << r.err;
  r = run("flexmb study m.dat --param L=1 --out no/such/folder");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("cannot make the study folder"), std::string::npos) << r.err;
  r = run("flexmb study collect .");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("is not a study folder"), std::string::npos) << r.err;
  r = run("flexmb study --help");
  EXPECT_EQ(r.code, 0);
  for (const char* o : {"--param", "--table", "--jobs", "--task", "--slurm", "--dry-run", "--buckling", "--derive"})
    EXPECT_NE(r.out.find(o), std::string::npos) << o;
}

TEST_F(StudyCli, ChangedAnalysesRunEveryVariantAgain) {
  Result r = run("flexmb study " + kPivot + " --param t=2e-4,3e-4 --modes -q --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("flexmb study " + kPivot + " --param t=2e-4,3e-4 --modes --nev 3 --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 run before with another template, parameters or analyses: they run again"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("ran 2 variants"), std::string::npos) << r.out;
  EXPECT_EQ(lines(slurp(dir_ / "s" / "study_summary.csv"))[0], "variant,name,t,status,dofs,f1_Hz,f2_Hz,f3_Hz,reason");
}

TEST_F(StudyCli, AVariantWhoseSummaryWasLostRunsAgain) {
  // The variants' files are committed without fsync: after a power failure a manifest may stand
  // beside an empty summary. Collect counts it as missing, and the study runs it again.
  Result r = run("flexmb study " + kPivot + " --param t=2e-4,3e-4 --modes -q --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string whole = slurp(dir_ / "s" / "study_summary.csv");
  std::ofstream(dir_ / "s" / "variants" / "v0001" / "cross_spring_pivot_study_summary.csv", std::ios::trunc);
  r = run("flexmb study collect s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 variants, 1 not run yet"), std::string::npos) << r.out;
  r = run("flexmb study " + kPivot + " --param t=2e-4,3e-4 --modes --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("1 finished before (skipped), 1 to run"), std::string::npos) << r.out;
  EXPECT_EQ(slurp(dir_ / "s" / "study_summary.csv"), whole);
}

TEST_F(StudyCli, SlurmScriptsRunByHandGiveTheSameTable) {
  const Result r = run("flexmb study " + kPivot + " " + kArgs +
                       " --out s --slurm --dry-run --tasks 3 --cpus-per-task 2 --sbatch=--time=00:10:00");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string script = slurp(dir_ / "s" / "slurm" / "study.sbatch");
  EXPECT_NE(script.find("#SBATCH --array=0-2\n"), std::string::npos) << script;
  EXPECT_NE(script.find("#SBATCH --cpus-per-task=2\n"), std::string::npos) << script;
  EXPECT_NE(script.find("#SBATCH --time=00:10:00\n"), std::string::npos) << script;
  EXPECT_NE(script.find("--task \"$SLURM_ARRAY_TASK_ID\" --of 3 --jobs \"${SLURM_CPUS_PER_TASK:-1}\" --quiet"),
            std::string::npos)
      << script;
  const std::string exec = script.substr(script.find("\nexec "));
  EXPECT_EQ(exec.find("--slurm"), std::string::npos) << exec;
  EXPECT_EQ(exec.find("--dry-run"), std::string::npos) << exec;
  EXPECT_EQ(exec.find("--tasks"), std::string::npos) << exec;
  EXPECT_EQ(exec.find("--cpus-per-task"), std::string::npos) << exec;
  EXPECT_EQ(exec.find("--sbatch"), std::string::npos) << exec;
  EXPECT_EQ(exec.find(" -q"), std::string::npos) << exec;
  const std::string collect = slurp(dir_ / "s" / "slurm" / "collect.sbatch");
  EXPECT_NE(collect.find("study collect s\n"), std::string::npos) << collect;
  EXPECT_FALSE(fs::exists(dir_ / "s" / "study_summary.csv"));
  // The scripts as Slurm would run them: each array task with its id, then the collect job.
  const Result tasks =
      run("for i in 0 1 2; do SLURM_ARRAY_TASK_ID=$i SLURM_CPUS_PER_TASK=1 bash s/slurm/study.sbatch "
          "|| exit 1; done; bash s/slurm/collect.sbatch");
  ASSERT_EQ(tasks.code, 0) << tasks.err;
  EXPECT_EQ(slurp(dir_ / "s" / "study_summary.csv"), referenceTable());
  // Without sbatch on the path, --slurm says what to do.
  const Result none = run("PATH=/nonexistent " + kFlexmb + " study " + kPivot + " " + kArgs + " --out n --slurm");
  EXPECT_EQ(none.code, 1);
  EXPECT_NE(none.err.find("sbatch failed"), std::string::npos) << none.err;
}

// One analysis, one set of files (issue 36): a study variant's modes, static, sweep and simulate
// files are the bytes `flexmb modes`, `static`, `sweep` and `simulate` write for the same model and
// options (the MAT files too: their header holds no time of writing).
TEST_F(StudyCli, VariantTablesAreTheCommandLinesBytes) {
  const Result r = run("flexmb study " + kPivot +
                       " --param t=0.2e-3:0.3e-3:2 --modes --static --buckling --sweep-node 4 --sweep-comp 3 "
                       "--sweep-from -0.1 --sweep-to 0.1 --sweep-steps 5 --simulate --t-end 0.002 --intervals 4 "
                       "--jobs 1 --out s -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path v = dir_ / "s" / "variants" / "v0002";
  const std::string model = (v / "cross_spring_pivot_study.dat").string();
  ASSERT_EQ(run("flexmb static " + model + " --buckling --format csv --out st.csv -q").code, 0);
  ASSERT_EQ(run("flexmb sweep " + model + " --node 4 --comp 3 --from -0.1 --to 0.1 --steps 5 --nev 6 --out sw -q").code,
            0);
  ASSERT_EQ(run("flexmb modes " + model + " --out md -q").code, 0);
  ASSERT_EQ(run("flexmb simulate " + model + " --t-end 0.002 --intervals 4 --format both --out sim -q").code, 0);
  for (const char* f :
       {"_x.csv", "_xd.csv", "_xdd.csv", "_e.csv", "_ed.csv", "_edd.csv", "_sig.csv", "_rot.csv", ".mat"})
    EXPECT_EQ(slurp(dir_ / ("sim" + std::string(f))), slurp(v / ("cross_spring_pivot_study" + std::string(f)))) << f;
  EXPECT_EQ(slurp(dir_ / "md_modes.csv"), slurp(v / "cross_spring_pivot_study_modes.csv"));
  const std::string staticCli = slurp(dir_ / "st.csv"), sweepCli = slurp(dir_ / "sw.csv");
  EXPECT_EQ(staticCli.rfind("load_step,initial_factor,load_factor,", 0), 0u) << staticCli.substr(0, 80);
  EXPECT_EQ(staticCli, slurp(v / "cross_spring_pivot_study_static.csv"));
  EXPECT_EQ(sweepCli, slurp(v / "cross_spring_pivot_study_sweep.csv"));
}

// The checks before a run are the command line's (analysis/RunSize.hpp): a variant whose simulation
// could not fit fails at once with the reason, the others run.
TEST_F(StudyCli, OversizedSimulationIsRefusedLikeTheCommandLine) {
  const Result r = run("flexmb study " + kPivot +
                       " --param t=0.2e-3:0.3e-3:2 --modes --simulate --t-end 0.002 --intervals 1000000000 --jobs 1 "
                       "--out s -q");
  const std::string table = slurp(dir_ / "s" / "study_summary.csv");
  EXPECT_NE(table.find("intervals"), std::string::npos) << table << r.err;
  EXPECT_EQ(table.find(",ok,"), std::string::npos) << table;
}

TEST_F(StudyCli, VariantsThatShareABasisRunOnItsReducedOperators) {
  // The guidance with its load's amplitude as parameter (a time function: not in the operators'
  // checksum), --target 1e-2, one worker: the first variant chooses the basis (4 modal vectors) and
  // trains the operators for the 25 (24 x ~730 evaluations to save on, past the rule's 12,700); the
  // others run on them, each meeting the target by its own estimate (issue 49 item 3).
  std::string text = slurp(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/straight_guidance.dat");
  const std::string load = "50*(1-cos(20*_pi*t))";
  ASSERT_NE(text.find(load), std::string::npos);
  text.replace(text.find(load), 2, "{A}");
  std::ofstream(dir_ / "g.dat") << text;
  const Result r = run("flexmb study g.dat --param A=44:50:25 --simulate --target 1e-2 --jobs 1 --out s");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = lines(slurp(dir_ / "s" / "study_summary.csv"));
  ASSERT_EQ(rows.size(), 26u);
  const std::vector<std::string> header = flexmb::io::splitCsvLine(rows[0]);
  const auto column = [&](const std::string& name) {
    return static_cast<size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const size_t ops = column("sim_operator_evaluations"), estimate = column("sim_reduction_estimate");
  ASSERT_LT(ops, header.size());
  ASSERT_LT(estimate, header.size());
  for (size_t k = 1; k < rows.size(); ++k) {
    const std::vector<std::string> cells = flexmb::io::splitCsvLine(rows[k]);
    if (k == 1)
      EXPECT_EQ(cells[ops], "0") << rows[k];  // the chosen candidate's run is its run (Eq. 19)
    else
      EXPECT_GT(std::stod(cells[ops]), 100) << rows[k];
    EXPECT_LE(std::stod(cells[estimate]), 1e-2) << rows[k];
  }
}
