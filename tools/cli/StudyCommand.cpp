// flexmb study: a design study, one template model and a table of parameter values, the same
// analyses on every variant, run on all cores (one worker process per variant: the analyses share
// nothing, ARPACK's state included), resumable, splittable into tasks (--task i --of n) and
// submittable to Slurm (--slurm); `flexmb study collect` joins the summaries into a table and a
// report. The recipe is analysis/Study.hpp; the file formats io/templates/ModelTemplate, io/templates/StudyTable and
// io/templates/StudySummary.
#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "analysis/SimulationFiles.hpp"
#include "analysis/Study.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/OutputFile.hpp"
#include "io/formats/ResultWriter.hpp"
#include "io/pictures/SvgPlot.hpp"
#include "io/templates/ModelTemplate.hpp"
#include "io/templates/StudySummary.hpp"
#include "io/templates/StudyTable.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Progress.hpp"
#include "tools/cli/StudySlurm.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace flexmb::cli {

namespace {

constexpr int kVariantBusy = 75;  // a worker's exit code: another process holds the variant's lock

const char* kUsage =
    "usage: flexmb study template.dat (--param name=from:to:count | --param name=v1,v2,... | --table values.csv)...\n"
    "                    [--modes] [--static] [--buckling [N]] [--check] [--sweep-node N ...] [--simulate ...]\n"
    "                    [--out folder] [--jobs N] [--task i --of n] [--slurm [--dry-run]]\n"
    "       flexmb study collect folder [--plot q1,q2,...]\n\n"
    "A design study: the template is a .dat file in which numbers may be placeholders, {t} or {2*t}\n"
    "(muParser expressions in the parameters; {name = expr} defines a value, {name ?= expr} a default);\n"
    "every variant (a table row, or a point of the --param grid) runs the analyses chosen here and\n"
    "writes <folder>/variants/<name>/ with a one-line summary. Rerunning the command resumes: finished\n"
    "variants are skipped. At the end the summaries are collected into <folder>/study_summary.csv and\n"
    "<folder>/study_report.html (a plot per quantity against each parameter). Default analyses:\n"
    "--modes --static. Reference: README (Design studies).";

std::string studyStem(const std::string& templatePath) { return fs::path(templatePath).stem().string(); }

std::string variantFolder(const std::string& dir, const std::string& name) {
  return (fs::path(dir) / "variants" / name).string();
}

// Everything a worker needs, made once before the workers are forked.
struct Study {
  std::string templatePath, stem, dir;
  io::ReadOptions readOptions;
  std::optional<io::ModelTemplate> model;
  analysis::StudyAnalyses analyses;
  std::vector<analysis::Variant> variants;
  std::vector<std::string> fingerprints;  // per variant
  std::vector<std::string> plot;          // quantities to plot (empty: all)
  bool quiet = false;
  std::string prefix(int k) const { return (fs::path(variantFolder(dir, variants[k].name)) / stem).string(); }
};

std::string parametersText(const io::ParameterValues& values) {
  std::string s;
  for (const auto& [n, v] : values) s += (s.empty() ? "" : ", ") + n + " = " + io::roundTripNumber(v);
  return s;
}

// ---- one variant's files ---------------------------------------------------------------------

void writeChecked(std::ofstream& f, const std::string& what) {
  f.flush();
  if (!f) throw std::runtime_error("cannot write '" + what + "': write failed");
}

void writeText(io::OutputSet& files, const std::string& suffix, const std::string& text) {
  std::ofstream f(files.temporaryFor(suffix), std::ios::binary);
  f << text;
  writeChecked(f, files.prefix() + suffix);
}

// `flexmb modes`'s table (analysis::modesTable).
void writeModes(io::OutputSet& files, const analysis::Frequencies& fr) {
  writeText(files, "_modes.csv", io::formatCsv(analysis::modesTable(fr)));
}

// `flexmb static`'s table (analysis::staticTable): the same bytes as the command line writes.
void writeStatic(io::OutputSet& files, const core::Model& model, const analysis::StaticRun& run, int buckling) {
  writeText(files, "_static.csv", io::formatCsv(analysis::staticTable(model, run, buckling)));
}

// `flexmb sweep`'s table (analysis::sweepTable).
void writeSweep(io::OutputSet& files, const core::Model& model, const analysis::SweepResult& r) {
  writeText(files, "_sweep.csv", io::formatCsv(analysis::sweepTable(model, r)));
}

void writeRecord(io::OutputSet& files, const io::StudyRecord& record) {
  std::ofstream f(files.temporaryFor("_summary.csv"));
  io::writeStudyRecord(f, record);
  writeChecked(f, files.prefix() + "_summary.csv");
}

// Holds the variant's lock file (flock: released when the process ends, however it ends).
class VariantLock {
 public:
  explicit VariantLock(const std::string& folder) {
    fd_ = ::open((fs::path(folder) / ".lock").c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    held_ = fd_ >= 0 && ::flock(fd_, LOCK_EX | LOCK_NB) == 0;
  }
  ~VariantLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool held() const { return held_; }

 private:
  int fd_ = -1;
  bool held_ = false;
};

// Temporaries a killed run left in the folder (*.part-<pid>); only while holding the lock.
void removeStaleTemporaries(const std::string& folder) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (e.path().filename().string().find(".part-") != std::string::npos) fs::remove(e.path(), ec);
}

// The worker: instantiates, reads and analyses variant k and writes its files, the manifest last.
// Returns the process's exit code (0: finished, ok or failed; 75: busy; 4: a file failed).
int runVariantFiles(const Study& s, int k) {
  const analysis::Variant& v = s.variants[k];
  const std::string folder = variantFolder(s.dir, v.name);
  std::error_code ec;
  fs::create_directories(folder, ec);
  VariantLock lock(folder);
  if (!lock.held()) return kVariantBusy;
  removeStaleTemporaries(folder);
  try {
    io::OutputSet files(s.prefix(k));
    files.setSync(false);  // resume checks the summary (analysis::variantState); see io::OutputSet::setSync
    files.checkWritable();
    io::StudyRecord record;
    std::string status = "complete";
    auto fail = [&](const std::string& reason) {
      record = analysis::failedRecord(v, reason);
      status = "failed: " + reason;
    };
    std::string text;
    io::ParameterValues names = v.values;  // with the template's own definitions, for --derive
    try {
      text = s.model->instantiate(v.values, &names);
    } catch (const io::TemplateError& e) {
      fail(e.what());
    }
    double seconds = 0.0;
    if (!text.empty()) {
      writeText(files, ".dat", text);
      const std::string shown = (fs::path("variants") / v.name / (s.stem + ".dat")).string();
      core::Model model;
      bool read = false;
      try {
        model = io::readDatString(text, shown, s.readOptions);
        read = true;
      } catch (const std::exception& e) {
        fail(e.what());
      }
      if (read) {
        // The analyses' own time: everything else (fork, template, reading, files) is the study's cost.
        const auto start = std::chrono::steady_clock::now();
        const analysis::VariantResults r = analysis::runVariant(model, s.analyses, names);
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (r.modes) writeModes(files, *r.modes);
        if (r.statics) writeStatic(files, model, *r.statics, s.analyses.statics->buckling);
        if (r.sweep) writeSweep(files, model, *r.sweep);
        if (r.trajectory) analysis::writeTrajectoryFiles(files, model, *r.trajectory, analysis::SimulationFiles());
        record = analysis::summaryRecord(v, r);
        if (!r.failure.empty()) status = "failed: " + r.failure;
      }
    }
    writeRecord(files, record);
    files.setting("command", "study");
    files.setting("template", s.templatePath);
    files.setting("variant", std::to_string(v.number) + " " + v.name);
    files.setting("parameters", parametersText(v.values));
    files.setting("fingerprint", s.fingerprints[k]);
    std::ostringstream secs;
    secs << seconds;
    files.setting("analysis seconds", secs.str());
    files.commit(status);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << v.name << ": " << e.what() << "\n";
    return kWriteFailed;
  }
  return kOk;
}

// A worker that died of a crash signal: the variant is recorded as failed (so the study goes on and
// a resume does not crash again; --rerun-failed retries it).
void recordCrash(const Study& s, int k, int signal) {
  const std::string folder = variantFolder(s.dir, s.variants[k].name);
  VariantLock lock(folder);
  if (!lock.held()) return;
  removeStaleTemporaries(folder);
  const std::string reason = "the analysis crashed (signal " + std::to_string(signal) + ": " + strsignal(signal) + ")";
  io::OutputSet files(s.prefix(k));
  files.setSync(false);
  files.checkWritable();
  writeRecord(files, analysis::failedRecord(s.variants[k], reason));
  files.setting("command", "study");
  files.setting("variant", std::to_string(s.variants[k].number) + " " + s.variants[k].name);
  files.setting("fingerprint", s.fingerprints[k]);
  files.commit("failed: " + reason);
}

// ---- the worker pool -------------------------------------------------------------------------

struct PoolReport {
  int finished = 0, failed = 0, busy = 0, writeFailed = 0, killed = 0;
  bool interrupted = false;
  double analysisSeconds = 0.0;
};

// Status and analysis seconds of a finished variant, from its manifest.
void readManifest(const std::string& path, std::string& status, double& seconds) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("status: ", 0) == 0) status = line.substr(8);
    if (line.rfind("analysis seconds: ", 0) == 0) seconds = std::atof(line.c_str() + 18);
  }
}

// A worker process that runs variants one after another: the parent writes a variant's index to
// `task`, the worker answers (index, exit code of runVariantFiles) on `done`. Forking once per
// worker instead of once per variant matters: a fresh process pays its page faults and lazy symbol
// bindings again (about 10 ms a variant on a virtual machine), a warm one does not. A crash still
// takes only the worker down: the parent records the variant it was running and forks another.
struct Worker {
  pid_t pid = -1;
  int task = -1, done = -1;  // the parent's ends
  int variant = -1;          // index being run, -1 when idle
};

[[noreturn]] void workerLoop(const Study& s, int task, int done) {
  ::signal(SIGINT, SIG_DFL);  // default actions: Ctrl-C ends the worker; nothing is committed
  ::signal(SIGTERM, SIG_DFL);
  ::signal(SIGPIPE, SIG_DFL);
  const int devnull = ::open("/dev/null", O_WRONLY);
  if (devnull >= 0) ::dup2(devnull, STDOUT_FILENO);
  for (int k = 0; ::read(task, &k, sizeof k) == static_cast<ssize_t>(sizeof k);) {
    const int reply[2] = {k, runVariantFiles(s, k)};
    if (::write(done, reply, sizeof reply) != static_cast<ssize_t>(sizeof reply)) break;
  }
  ::_exit(kOk);
}

// Forks a worker; false when the system refuses (the caller stops starting variants).
bool startWorker(const Study& s, std::vector<Worker>& workers, Worker& w) {
  int toWorker[2], toParent[2];
  if (::pipe(toWorker) != 0) return false;
  if (::pipe(toParent) != 0) {
    ::close(toWorker[0]), ::close(toWorker[1]);
    return false;
  }
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // The other workers' pipe ends must not stay open here, or they would never see end-of-file.
    for (const Worker& o : workers)
      if (&o != &w && o.pid > 0) ::close(o.task), ::close(o.done);
    ::close(toWorker[1]), ::close(toParent[0]);
    workerLoop(s, toWorker[0], toParent[1]);
  }
  ::close(toWorker[0]), ::close(toParent[1]);
  if (pid < 0) {
    ::close(toWorker[1]), ::close(toParent[0]);
    return false;
  }
  w.pid = pid, w.task = toWorker[1], w.done = toParent[0], w.variant = -1;
  return true;
}

PoolReport runPool(const Study& s, const std::vector<int>& pending, int jobs) {
  PoolReport rep;
  installInterruptHandler();
  const std::atomic<bool>* stop = interruptFlag();
  struct sigaction ignorePipe {
  }, oldPipe{};
  ignorePipe.sa_handler = SIG_IGN;
  ::sigaction(SIGPIPE, &ignorePipe, &oldPipe);  // a dead worker's task pipe: EPIPE, not the end of the study
  std::vector<Worker> workers(static_cast<std::size_t>(jobs));
  size_t next = 0;
  int failuresShown = 0;
  bool cannotStart = false;
  Progress progress("study", !s.quiet);
  std::cout.flush();
  std::cerr.flush();
  // The outcome of variant k run by a worker: its exit code, or the signal that ended it.
  auto finished = [&](int k, bool exited, int code, int sig) {
    const analysis::Variant& v = s.variants[k];
    if (exited && code == kOk) {
      std::string st;
      double seconds = 0.0;
      readManifest(s.prefix(k) + "_run.txt", st, seconds);
      rep.analysisSeconds += seconds;
      ++rep.finished;
      if (st.rfind("failed", 0) == 0) {
        ++rep.failed;
        if (failuresShown++ < 10) {
          progress.finish();
          std::cerr << "flexmb: " << v.name << " (" << parametersText(v.values) << ") " << st << "\n";
        }
      }
    } else if (exited && code == kVariantBusy) {
      ++rep.busy;
    } else if (exited) {
      ++rep.writeFailed;
    } else if (sig == SIGINT || sig == SIGTERM || sig == SIGHUP || sig == SIGKILL || rep.interrupted || *stop) {
      // Stopped from outside (Ctrl-C, a scheduler, the OOM killer): run again on resume.
      if (!*stop && !rep.interrupted) {
        ++rep.killed;
        progress.finish();
        std::cerr << "flexmb: " << v.name << " was stopped by signal " << sig << " (" << strsignal(sig)
                  << "; out of memory or a time limit?): it runs again when the study is resumed\n";
      }
    } else {
      try {
        recordCrash(s, k, sig);
        ++rep.finished;
        ++rep.failed;
      } catch (const std::exception& e) {
        ++rep.writeFailed;
        std::cerr << "flexmb: " << v.name << ": " << e.what() << "\n";
      }
      progress.finish();
      std::cerr << "flexmb: " << v.name << " (" << parametersText(v.values) << ") crashed (signal " << sig << ": "
                << strsignal(sig) << "); recorded as failed\n";
    }
    progress.update(rep.finished, static_cast<long>(pending.size()), "variants");
  };
  // A worker whose pipe closed: reaped; the variant it ran is reported with its end.
  auto reap = [&](Worker& w) {
    ::close(w.task), ::close(w.done);
    int status = 0;
    while (::waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {}
    if (w.variant >= 0) {
      const bool exited = WIFEXITED(status);
      // Exited normally while running a variant: it could not answer (a write failure).
      finished(w.variant, exited, exited ? kWriteFailed : 0, WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    }
    w = Worker{};
  };
  for (;;) {
    if (*stop && !rep.interrupted) {  // Ctrl-C (or SIGTERM from a scheduler): stop the workers too
      rep.interrupted = true;
      for (const Worker& w : workers)
        if (w.pid > 0) ::kill(w.pid, SIGINT);
    }
    // Hand out variants to idle workers (starting workers as needed); close idle ones at the end.
    for (Worker& w : workers) {
      if (w.pid > 0 && w.variant >= 0) continue;
      if (*stop || next >= pending.size() || cannotStart) {
        if (w.pid > 0) reap(w);  // idle: end-of-file ends it
        continue;
      }
      if (w.pid < 0 && !startWorker(s, workers, w)) {
        std::cerr << "flexmb: cannot start a worker process: " << std::strerror(errno) << "\n";
        rep.interrupted = true;
        cannotStart = true;
        continue;
      }
      const int k = pending[next++];
      w.variant = k;
      if (::write(w.task, &k, sizeof k) != static_cast<ssize_t>(sizeof k)) reap(w);  // died idle: reported
    }
    std::vector<pollfd> fds;
    std::vector<Worker*> of;
    for (Worker& w : workers)
      if (w.pid > 0) fds.push_back({w.done, POLLIN, 0}), of.push_back(&w);
    if (fds.empty()) break;
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;  // a signal: the loop's first check forwards an interrupt
      break;
    }
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (!fds[i].revents) continue;
      Worker& w = *of[i];
      int reply[2];
      const ssize_t got = ::read(w.done, reply, sizeof reply);
      if (got == static_cast<ssize_t>(sizeof reply)) {
        w.variant = -1;
        finished(reply[0], true, reply[1], 0);
      } else if (got < 0 && errno == EINTR) {
        continue;
      } else {
        reap(w);  // end-of-file: the worker died (a crash, a signal)
      }
    }
  }
  ::sigaction(SIGPIPE, &oldPipe, nullptr);
  progress.finish();
  if (*stop) rep.interrupted = true;
  if (failuresShown > 10) std::cerr << "flexmb: ... " << failuresShown - 10 << " more failed (see the table)\n";
  return rep;
}

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

std::map<std::string, std::string> readKeyValues(const std::string& path) {
  std::map<std::string, std::string> kv;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    const auto c = line.find(": ");
    if (c != std::string::npos) kv[line.substr(0, c)] += (kv.count(line.substr(0, c)) ? "\n" : "") + line.substr(c + 2);
  }
  return kv;
}

std::vector<std::string> splitList(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string x; std::getline(in, x, sep);)
    if (!x.empty()) out.push_back(x);
  return out;
}

std::string fileSafe(const std::string& s) {
  std::string o;
  for (char c : s) o += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ? c : '_';
  return o;
}

// Joins the variants' summaries into <dir>/study_summary.csv, study_report.html and one SVG per
// quantity and parameter. Variants without a finished summary of the current study are "missing".
int collect(const std::string& dir, std::vector<std::string> plot, bool quiet) {
  const auto setup = readKeyValues((fs::path(dir) / "study.txt").string());
  if (!setup.count("stem")) {
    std::cerr << "flexmb: " << dir << " is not a study folder (no study.txt; `flexmb study` writes it)\n";
    return kInputError;
  }
  const std::string stem = setup.at("stem");
  std::ifstream vin((fs::path(dir) / "variants.csv").string());
  std::vector<io::StudyRecord> records;
  int missing = 0;
  try {
    std::string line;
    if (!std::getline(vin, line)) throw std::runtime_error((fs::path(dir) / "variants.csv").string() + ": empty");
    const auto header = io::splitCsvLine(line);
    while (std::getline(vin, line)) {
      if (line.empty()) continue;
      const auto cells = io::splitCsvLine(line);
      if (cells.size() != header.size() || header.size() < 3)
        throw std::runtime_error((fs::path(dir) / "variants.csv").string() + ": a row does not match the header");
      analysis::Variant v;
      v.number = std::stoi(cells[0]);
      v.name = cells[1];
      for (size_t i = 3; i < cells.size(); ++i) v.values.emplace_back(header[i], std::stod(cells[i]));
      const std::string prefix = (fs::path(variantFolder(dir, v.name)) / stem).string();
      // Finished for this study: its manifest names the fingerprint the study gave the variant.
      const auto manifest = readKeyValues(prefix + "_run.txt");
      const auto fp = manifest.find("fingerprint");
      std::optional<io::StudyRecord> summary;
      if (fp != manifest.end() && fp->second == cells[2]) {
        try {
          summary = io::readStudyRecord(prefix + "_summary.csv");
        } catch (const std::exception&) {  // unsynced files after a power failure: missing, runs again
        }
      }
      if (summary) {
        summary->variant = v.number;
        records.push_back(std::move(*summary));
      } else {
        io::StudyRecord r = analysis::failedRecord(v, "not run yet");
        r.status = "missing";
        records.push_back(std::move(r));
        ++missing;
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kInputError;
  }
  if (plot.empty() && setup.count("plot")) plot = splitList(setup.at("plot"), ' ');
  io::StudyReport report;
  report.title = "Study of " + fs::path(setup.at("template")).filename().string();
  report.lines.push_back("template: " + setup.at("template"));
  if (setup.count("analysis"))
    for (const auto& l : splitList(setup.at("analysis"), '\n')) report.lines.push_back("analysis: " + l);
  if (setup.count("command")) report.lines.push_back("command: " + setup.at("command"));
  report.quantities = plot;
  const auto quantities = plot.empty() ? io::plottableQuantities(records) : plot;
  try {
    io::OutputSet files((fs::path(dir) / "study").string());
    files.setSync(false);  // made again from the variants by `flexmb study collect` at any time
    files.checkWritable();
    {
      std::ofstream f(files.temporaryFor("_summary.csv"));
      io::writeStudyTable(f, records);
      writeChecked(f, files.prefix() + "_summary.csv");
    }
    writeText(files, "_report.html", io::renderStudyReport(report, records));
    std::vector<std::string> params;
    if (!records.empty())
      for (const auto& [n, v] : records.front().parameters) params.push_back(n);
    for (const auto& q : quantities)
      for (const auto& p : params) {
        std::string suffix = "_";
        suffix.append(fileSafe(q)).append("_vs_").append(fileSafe(p)).append(".svg");
        io::writeSvg(files.temporaryFor(suffix), io::studyPlot(records, q, p));
      }
    files.setting("command", "study collect");
    files.setting("variants", std::to_string(records.size()));
    files.setting("missing", std::to_string(missing));
    files.commit(missing ? "incomplete: " + std::to_string(missing) + " variants not run yet" : "complete");
    if (!quiet)
      std::cout << "wrote " << files.prefix() << "_summary.csv and " << files.prefix() << "_report.html ("
                << records.size() << " variants" << (missing ? ", " + std::to_string(missing) + " not run yet" : "")
                << ")\n";
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  return kOk;
}

int runCollect(const std::vector<std::string>& args) {
  ModelOptions m;
  std::string plot;
  po::options_description d("options");
  d.add_options()("plot", po::value(&plot),
                  "quantities to plot, comma-separated (default: the study's --plot, else all)")(
      "quiet,q", po::bool_switch(&m.quiet), "print nothing but errors");
  if (auto rc = parseCommand(args, d, m, "usage: flexmb study collect folder [--plot q1,q2,...]")) return *rc;
  return collect(m.file, splitList(plot, ','), m.quiet);
}

int availableCores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN));
}

// The study's command line.
struct StudyArgs {
  ModelOptions m;
  std::vector<std::string> params, derive, plot;
  std::string table, out;
  bool check = false, modes = false, statics = false, simulate = false, rerunFailed = false;
  int nev = 6, steps = 0, buckling = 0, jobs = 0, task = -1, of = 0;
  std::vector<int> stiffness;
  analysis::SweepOptions sw;
  double tEnd = 0, relTol = 0, absTol = 0;
  int intervals = -1;
  std::string integrator = "ode45";
  double target = NAN;  // --target (NaN: not given)
  SlurmOptions slurm;
  StudyArgs() { sw.node = 0; }
};

std::optional<int> parseStudyArgs(const std::vector<std::string>& args, StudyArgs& sa) {
  po::options_description d = commonModelOptions(sa.m);
  po::options_description pd("parameters");
  pd.add_options()("param", po::value(&sa.params)->composing(),
                   "a grid axis: name=from:to:count, name=v1,v2,... or name=value (repeatable: every combination)")(
      "table", po::value(&sa.table),
      "CSV of parameter values: one column per parameter (and optionally `name`), a row "
      "per variant (combined with every --param grid point)");
  po::options_description ad("analyses (chosen once for the study; default --modes --static)");
  ad.add_options()("check", po::bool_switch(&sa.check),
                   "the kinematic rank check (a variant that is not well posed fails)")(
      "modes", po::bool_switch(&sa.modes), "eigenfrequencies in the initial configuration (flexmb modes)")(
      "static", po::bool_switch(&sa.statics), "static load steps (flexmb static) with frequencies in each equilibrium")(
      "nev", po::value(&sa.nev)->notifier(atLeast("nev", 1)), "eigenfrequencies (modes, static, sweep; default 6)")(
      "steps", po::value(&sa.steps)->notifier(atLeast("steps", 1)), "static load steps (default: the file's ITERSTEP)")(
      "buckling", po::value(&sa.buckling)->implicit_value(3)->notifier(atLeast("buckling", 1)),
      "buckling load factors in each equilibrium (default 3 when given; implies --static)")(
      "stiffness", po::value(&sa.stiffness)->composing(),
      "node label whose tangent stiffness the static step reports (repeatable; default: the loaded nodes)")(
      "sweep-node", po::value(&sa.sw.node), "sweep: node label of the prescribed coordinate (runs flexmb sweep)")(
      "sweep-comp", po::value(&sa.sw.component)->default_value(1)->notifier(atLeast("sweep-comp", 1)),
      "sweep: its component")("sweep-from", po::value(&sa.sw.from)->notifier(finite("sweep-from")),
                              "sweep: first value")("sweep-to", po::value(&sa.sw.to)->notifier(finite("sweep-to")),
                                                    "sweep: last value")(
      "sweep-steps", po::value(&sa.sw.steps)->default_value(10)->notifier(atLeast("sweep-steps", 1)),
      "sweep: configurations")("simulate", po::bool_switch(&sa.simulate), "forward dynamics (flexmb simulate)")(
      "t-end", po::value(&sa.tEnd)->notifier(positive("t-end")), "simulate: end time")(
      "reltol", po::value(&sa.relTol)->notifier(positive("reltol")), "simulate: relative tolerance")(
      "abstol", po::value(&sa.absTol)->notifier(positive("abstol")), "simulate: absolute tolerance")(
      "intervals", po::value(&sa.intervals)->notifier(atLeast("intervals", 0)), "simulate: output intervals")(
      "integrator", po::value(&sa.integrator), "simulate: ode45 (default), bdf, auto or galpha (as flexmb simulate)")(
      "target", po::value(&sa.target)->notifier(finite("target")),
      "simulate: reduce each variant with the smallest modal basis whose reduction error estimate meets this "
      "target (0 < EPS < 1; columns sim_basis_vectors, sim_reduction_estimate)")(
      "derive", po::value(&sa.derive)->composing(),
      "a derived quantity name=expression in the parameters and quantities, e.g. "
      "stress=6*max_bending/(w*t^2) (repeatable)");
  po::options_description rd("running");
  rd.add_options()("out", po::value(&sa.out), "the study folder (default: <template>_study)")(
      "jobs,j", po::value(&sa.jobs)->notifier(atLeast("jobs", 1)), "variants at once (default: every core)")(
      "task", po::value(&sa.task)->notifier(atLeast("task", 0)), "run only task i's share: variants i, i+n, i+2n, ...")(
      "of", po::value(&sa.of)->notifier(atLeast("of", 1)), "the number of tasks n (with --task)")(
      "rerun-failed", po::bool_switch(&sa.rerunFailed), "run failed variants again (finished ones are skipped)")(
      "plot", po::value<std::string>()->notifier([&](const std::string& v) { sa.plot = splitList(v, ','); }),
      "quantities to plot in the report, comma-separated (default: every quantity)");
  po::options_description sd("Slurm");
  addSlurmOptions(sd, sa.slurm);
  d.add(pd).add(ad).add(rd).add(sd);
  if (auto rc = parseCommand(args, d, sa.m, kUsage)) return *rc;
  if ((sa.task >= 0) != (sa.of > 0)) {
    std::cerr << "flexmb: --task and --of go together (task i of n, 0 <= i < n)\n";
    return kUsageError;
  }
  if (sa.task >= sa.of && sa.of > 0) {
    std::cerr << "flexmb: --task " << sa.task << " --of " << sa.of << ": the task is a number from 0 to " << sa.of - 1
              << "\n";
    return kUsageError;
  }
  if (sa.slurm.submit && sa.task >= 0) {
    std::cerr << "flexmb: --slurm writes the tasks itself; leave out --task and --of\n";
    return kUsageError;
  }
  if (sa.slurm.dryRun && !sa.slurm.submit) {
    std::cerr << "flexmb: --dry-run goes with --slurm (it writes the scripts without submitting them)\n";
    return kUsageError;
  }
  return std::nullopt;
}

// The analyses every variant runs, from the command line (a usage error: its exit code).
std::optional<int> chooseStudyAnalyses(const std::vector<std::string>& args, StudyArgs& sa,
                                       analysis::StudyAnalyses& a) {
  const bool sweepAsked = sa.sw.node != 0;
  a.check = sa.check;
  if (sa.buckling > 0) sa.statics = true;
  if (!sa.check && !sa.modes && !sa.statics && !sweepAsked && !sa.simulate) sa.modes = sa.statics = true;
  if (sa.modes) a.modes = sa.nev;
  if (sa.statics) a.statics = analysis::StudyAnalyses::Statics{sa.nev, sa.steps, sa.buckling};
  if (sweepAsked) {
    const auto given = [&](const char* o) {
      for (const auto& x : args)
        if (x == std::string("--") + o || x.rfind(std::string("--") + o + "=", 0) == 0) return true;
      return false;
    };
    if (!given("sweep-from") || !given("sweep-to")) {
      std::cerr << "flexmb: --sweep-node needs --sweep-from and --sweep-to\n";
      return kUsageError;
    }
    sa.sw.nev = sa.nev;
    a.sweep = sa.sw;
  }
  if (sa.simulate) {
    analysis::SimulationOptions o;
    const auto in = analysis::parseIntegrator(sa.integrator);
    if (!in) {
      std::cerr << "flexmb: --integrator must be ode45, bdf, auto or galpha, not '" << sa.integrator << "'\n";
      return kUsageError;
    }
    o.integrator = *in;
    if (sa.tEnd > 0) o.tEnd = sa.tEnd;
    if (sa.relTol > 0) o.relTol = sa.relTol;
    if (sa.absTol > 0) o.absTol = sa.absTol;
    if (sa.intervals >= 0) o.intervals = sa.intervals;
    o.keepStates = true;
    a.simulation = o;
    if (!std::isnan(sa.target)) {
      if (!(sa.target > 0 && sa.target < 1)) {
        std::cerr << "flexmb: --target must be between 0 and 1 (the reduction error relative to the motion)\n";
        return kUsageError;
      }
      a.reductionTarget = sa.target;
    }
  } else if (!std::isnan(sa.target)) {
    std::cerr << "flexmb: --target applies to --simulate\n";
    return kUsageError;
  }
  a.stiffnessNodes = sa.stiffness;
  for (const auto& dv : sa.derive) {
    const auto eq = dv.find('=');
    const std::string name = eq == std::string::npos ? "" : dv.substr(0, eq);
    if (!io::isParameterName(name) || eq + 1 >= dv.size()) {
      std::cerr << "flexmb: --derive " << dv << ": write name=expression (a name is a letter or '_' then letters, "
                << "digits or '_')\n";
      return kUsageError;
    }
    a.derived.emplace_back(name, dv.substr(eq + 1));
  }
  return std::nullopt;
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
  const auto start = std::chrono::steady_clock::now();
  const PoolReport rep = runPool(s, pending, std::min<int>(jobs, std::max<size_t>(1, pending.size())));
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

int runStudy(const std::vector<std::string>& args) {
  if (!args.empty() && args[0] == "collect") return runCollect({args.begin() + 1, args.end()});
  StudyArgs sa;
  if (auto rc = parseStudyArgs(args, sa)) return *rc;
  Study s;
  s.templatePath = sa.m.file;
  s.stem = studyStem(sa.m.file);
  s.quiet = sa.m.quiet;
  s.plot = sa.plot;
  if (sa.m.dialect == "95" || sa.m.dialect == "spacar95") s.readOptions.dialect = core::Dialect::Spacar95;
  if (sa.m.dialect == "2013" || sa.m.dialect == "spacar2013") s.readOptions.dialect = core::Dialect::Spacar2013;
  if (sa.m.elongation == "plain") s.readOptions.elongation = core::ElongationDefinition::Plain;
  if (sa.m.elongation == "corrected") s.readOptions.elongation = core::ElongationDefinition::BendingCorrected;
  if (auto rc = chooseStudyAnalyses(args, sa, s.analyses)) return *rc;
  if (auto rc = prepareStudy(args, sa, s)) return *rc;
  if (sa.slurm.submit) return submitStudy(sa.slurm, args, s.dir, static_cast<int>(s.variants.size()), sa.m.quiet);
  return runPendingVariants(sa, s);
}

}  // namespace flexmb::cli
