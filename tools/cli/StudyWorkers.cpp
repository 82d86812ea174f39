// flexmb study's workers: each variant instantiated, read, analysed and written by a worker process
// (one per job, forked once) under the variant's lock; a crashed worker's variant recorded as failed.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "analysis/SimulationFiles.hpp"
#include "io/formats/ResultWriter.hpp"
#include "tools/cli/Progress.hpp"
#include "tools/cli/StudyCommand.hpp"

namespace fs = std::filesystem;

namespace flexmb::cli::study {

namespace {

constexpr int kVariantBusy = 75;  // a worker's exit code: another process holds the variant's lock

// ---- one variant's files ---------------------------------------------------------------------

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

}  // namespace

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

}  // namespace flexmb::cli::study
