// flexmb study: a design study, one template model and a table of parameter values, the same
// analyses on every variant, run on all cores (one worker process per variant: the analyses share
// nothing, ARPACK's state included), resumable, splittable into tasks (--task i --of n) and
// submittable to Slurm (--slurm); `flexmb study collect` joins the summaries into a table and a
// report. The recipe is analysis/Study.hpp; the file formats io/templates/ModelTemplate, io/templates/StudyTable and
// io/templates/StudySummary.
// This file: the command (the study folder, what is left to run); the rest: tools/cli/StudyCommand.hpp.
#include <sched.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "tools/cli/StudyCommand.hpp"

namespace fs = std::filesystem;

namespace flexmb::cli {

namespace study {

std::string variantFolder(const std::string& dir, const std::string& name) {
  return (fs::path(dir) / "variants" / name).string();
}

std::string Study::prefix(int k) const { return (fs::path(variantFolder(dir, variants[k].name)) / stem).string(); }

std::string parametersText(const io::ParameterValues& values) {
  std::string s;
  for (const auto& [n, v] : values) s += (s.empty() ? "" : ", ") + n + " = " + io::roundTripNumber(v);
  return s;
}

void writeChecked(std::ofstream& f, const std::string& what) {
  f.flush();
  if (!f) throw std::runtime_error("cannot write '" + what + "': write failed");
}

void writeText(io::OutputSet& files, const std::string& suffix, const std::string& text) {
  std::ofstream f(files.temporaryFor(suffix), std::ios::binary);
  f << text;
  writeChecked(f, files.prefix() + suffix);
}

std::vector<std::string> splitList(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string x; std::getline(in, x, sep);)
    if (!x.empty()) out.push_back(x);
  return out;
}

namespace {

std::string studyStem(const std::string& templatePath) { return fs::path(templatePath).stem().string(); }

// ---- study files -----------------------------------------------------------------------------

// Writes path atomically unless it already holds exactly `text` (every task of a split writes the
// same study files; two at once are harmless).
void writeShared(const std::string& path, const std::string& text) {
  {
    std::ifstream in(path, std::ios::binary);
    std::stringstream old;
    old << in.rdbuf();
    if (in && old.str() == text) return;
  }
  try {
    io::OutputFile f(path);
    f << text;
    f.commit();
  } catch (const std::exception&) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream now;
    now << in.rdbuf();
    if (!(in && now.str() == text)) throw;  // another task wrote the same text at the same moment
  }
}

std::string studyDescription(const Study& s, const std::vector<std::string>& args) {
  std::ostringstream o;
  o << "flexmb study\n";
  o << "template: " << s.templatePath << "\n";
  o << "stem: " << s.stem << "\n";
  o << "variants: " << s.variants.size() << "\n";
  o << "parameters:";
  for (const auto& [n, v] : s.variants.front().values) o << " " << n;
  o << "\n";
  std::istringstream a(s.analyses.describe());
  for (std::string line; std::getline(a, line);) o << "analysis: " << line << "\n";
  if (!s.plot.empty()) {
    o << "plot:";
    for (const auto& p : s.plot) o << " " << p;
    o << "\n";
  }
  for (const auto& [key, value] : s.accuracySettings) o << key << ": " << value << "\n";
  o << "command: flexmb study";  // as every task of a split has it (the same file from each)
  for (const auto& x : taskArguments(args)) o << " " << shellQuote(x);
  o << "\n";
  return o.str();
}

std::string variantsTable(const Study& s) {
  std::ostringstream o;
  o << "variant,name,fingerprint";
  for (const auto& [n, v] : s.variants.front().values) o << "," << n;
  o << "\n";
  for (size_t k = 0; k < s.variants.size(); ++k) {
    o << s.variants[k].number << "," << s.variants[k].name << "," << s.fingerprints[k];
    for (const auto& [n, v] : s.variants[k].values) o << "," << io::roundTripNumber(v);
    o << "\n";
  }
  return o.str();
}

int availableCores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN));
}

// The template, its variants and the study folder with its description (an exit code on failure).
std::optional<int> prepareStudy(const std::vector<std::string>& args, const StudyArgs& sa, Study& s) {
  // The template and the variants.
  try {
    s.model = io::ModelTemplate::fromFile(sa.m.file);
    std::vector<io::ParameterAxis> grid;
    for (const auto& p : sa.params) grid.push_back(io::parseParameterAxis(p));
    std::optional<io::ParameterTable> t;
    if (!sa.table.empty()) t = io::readParameterTable(sa.table);
    s.variants = analysis::expandVariants(t ? &*t : nullptr, grid);
    std::vector<std::string> names;
    for (const auto& [n, v] : s.variants.front().values) names.push_back(n);
    s.model->check(names);
  } catch (const std::invalid_argument& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kUsageError;
  } catch (const std::exception& e) {
    std::cerr << (dynamic_cast<const io::TemplateError*>(&e) ? "" : "flexmb: ") << e.what() << "\n";
    return kInputError;
  }
  if (auto rc = planStudyMesh(sa, s)) return *rc;
  for (const auto& v : s.variants)
    s.fingerprints.push_back(analysis::variantFingerprint(s.model->text(), v.values, s.analyses, FLEXMB_VERSION));
  // The study folder.
  s.dir = sa.out.empty() ? s.stem + (s.stem.size() >= 6 && s.stem.ends_with("_study") ? "" : "_study") : sa.out;
  while (s.dir.size() > 1 && s.dir.back() == '/') s.dir.pop_back();
  {
    std::error_code ec;
    fs::create_directory(s.dir, ec);
    if (!fs::is_directory(s.dir)) {
      std::cerr << "flexmb: cannot make the study folder '" << s.dir << "'"
                << (ec ? ": " + ec.message() : std::string()) << " (its parent folder must exist)\n";
      return kInputError;
    }
    fs::create_directories(fs::path(s.dir) / "variants", ec);
  }
  try {
    writeShared((fs::path(s.dir) / "study.txt").string(), studyDescription(s, args));
    writeShared((fs::path(s.dir) / "variants.csv").string(), variantsTable(s));
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  return std::nullopt;
}

// The variants of this task that have not finished, run in a pool; then the table and report.
int runPendingVariants(const StudyArgs& sa, Study& s) {
  // What is left to run (resume).
  const std::vector<int> share = sa.task >= 0 ? analysis::taskShare(static_cast<int>(s.variants.size()), sa.task, sa.of)
                                              : analysis::taskShare(static_cast<int>(s.variants.size()), 0, 1);
  std::vector<int> pending;
  int done = 0, stale = 0;
  for (int k : share) {
    const auto state =
        analysis::variantState(s.prefix(k) + "_run.txt", s.fingerprints[k], s.prefix(k) + "_summary.csv");
    if (state == analysis::VariantState::Finished ||
        (state == analysis::VariantState::FinishedFailed && !sa.rerunFailed)) {
      ++done;
      continue;
    }
    if (state == analysis::VariantState::Stale) ++stale;
    pending.push_back(k);
  }
  const int jobs = sa.jobs > 0 ? sa.jobs : availableCores();
  if (!sa.m.quiet) {
    std::cout << "study: " << s.variants.size() << " variants of " << sa.m.file;
    if (sa.task >= 0) std::cout << ", task " << sa.task << " of " << sa.of << ": " << share.size() << " of them";
    std::cout << "\n";
    if (done > 0) std::cout << "  " << done << " finished before (skipped), " << pending.size() << " to run\n";
    if (stale > 0)
      std::cout << "  " << stale << " run before with another template, parameters or analyses: they run again\n";
  }
  const int workers = std::min<int>(jobs, std::max<size_t>(1, pending.size()));
  // simulate --target: the variants a worker runs, which may share a basis and its reduced operators.
  s.analyses.sharingVariants = static_cast<int>((pending.size() + workers - 1) / workers);
  const auto start = std::chrono::steady_clock::now();
  const PoolReport rep = runPool(s, pending, workers);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!sa.m.quiet && rep.finished > 0) {
    std::cout << "  ran " << rep.finished << " variants in " << std::setprecision(3) << wall << " s with "
              << std::min<int>(jobs, pending.size()) << " job(s): " << rep.finished - rep.failed << " ok, "
              << rep.failed << " failed; their analyses took " << rep.analysisSeconds << " s";
    if (jobs == 1)
      std::cout << ", the study " << std::setprecision(2) << 1e3 * (wall - rep.analysisSeconds) / rep.finished
                << " ms per variant besides";
    std::cout << "\n";
  }
  if (rep.interrupted) {
    std::cerr << "flexmb: interrupted: " << done + rep.finished << " of " << share.size()
              << " variants finished; the same command resumes\n";
    // The variants finished so far in the sa.table and report (marked incomplete), as after a run.
    if (sa.task < 0) collect(s.dir, s.plot, sa.m.quiet);
    return interruptedExitCode();
  }
  if (rep.busy > 0) std::cerr << "flexmb: " << rep.busy << " variants were being run by another process (skipped)\n";
  if (rep.writeFailed > 0) {
    std::cerr << "flexmb: " << rep.writeFailed << " variants could not be written (see above)\n";
    return kWriteFailed;
  }
  if (sa.task >= 0) {
    if (!sa.m.quiet)
      std::cout << "task " << sa.task << " of " << sa.of << " done; when every task is: flexmb study collect " << s.dir
                << "\n";
    return kOk;
  }
  return collect(s.dir, s.plot, sa.m.quiet);
}

}  // namespace

}  // namespace study

int runStudy(const std::vector<std::string>& args) {
  if (!args.empty() && args[0] == "collect") return study::runCollect({args.begin() + 1, args.end()});
  study::StudyArgs sa;
  if (auto rc = study::parseStudyArgs(args, sa)) return *rc;
  study::Study s;
  s.templatePath = sa.m.file;
  s.stem = study::studyStem(sa.m.file);
  s.quiet = sa.m.quiet;
  s.plot = sa.plot;
  if (sa.m.dialect == "95" || sa.m.dialect == "spacar95") s.readOptions.dialect = core::Dialect::Spacar95;
  if (sa.m.dialect == "2013" || sa.m.dialect == "spacar2013") s.readOptions.dialect = core::Dialect::Spacar2013;
  if (sa.m.elongation == "plain") s.readOptions.elongation = core::ElongationDefinition::Plain;
  if (sa.m.elongation == "corrected") s.readOptions.elongation = core::ElongationDefinition::BendingCorrected;
  s.readOptions.refine = sa.m.refine;
  s.readOptions.refinedResults = sa.m.refinedResults;
  if (auto rc = study::chooseStudyAnalyses(args, sa, s.analyses)) return *rc;
  if (auto rc = study::prepareStudy(args, sa, s)) return *rc;
  if (sa.slurm.submit) return submitStudy(sa.slurm, args, s.dir, static_cast<int>(s.variants.size()), sa.m.quiet);
  return study::runPendingVariants(sa, s);
}

}  // namespace flexmb::cli
