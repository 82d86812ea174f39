#include "tools/cli/StudySlurm.hpp"

#include <unistd.h>

#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>

#include "io/formats/OutputFile.hpp"
#include "tools/cli/Commands.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace flexmb::cli {

namespace {

std::string selfPath() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("flexmb") : p.string();
}

// Runs a command, returns its standard output (empty and ok = false when it fails).
std::string capture(const std::string& command, bool& ok) {
  std::string out;
  std::FILE* p = ::popen(command.c_str(), "r");
  if (!p) {
    ok = false;
    return out;
  }
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  ok = ::pclose(p) == 0;
  return out;
}

// sbatch --parsable prints "jobid" or "jobid;cluster".
std::string jobId(const std::string& printed) {
  std::string id;
  for (char c : printed) {
    if (c == ';' || c == '\n') break;
    id += c;
  }
  return id;
}

void writeScript(const std::string& path, const std::string& text) {
  io::OutputFile f(path);
  f << text;
  f.commit();
}

}  // namespace

void addSlurmOptions(po::options_description& d, SlurmOptions& o) {
  d.add_options()("slurm", po::bool_switch(&o.submit),
                  "run the study as a Slurm job array and a collect job after it (scripts in <folder>/slurm/)")(
      "dry-run", po::bool_switch(&o.dryRun), "with --slurm: write the scripts, do not submit them")(
      "tasks", po::value(&o.tasks)->notifier(atLeast("tasks", 1)),
      "with --slurm: array tasks (default: one per variant, at most 100)")(
      "cpus-per-task", po::value(&o.cpusPerTask)->notifier(atLeast("cpus-per-task", 1)),
      "with --slurm: cores per task, each running that many variants at once (default 1)")(
      "sbatch", po::value(&o.sbatch)->composing(),
      "with --slurm: an extra #SBATCH option for both jobs, e.g. --sbatch=--time=02:00:00 "
      "--sbatch=--partition=short (repeatable)");
}

std::string shellQuote(const std::string& s) {
  bool plain = !s.empty();
  for (char c : s)
    plain = plain &&
            (std::isalnum(static_cast<unsigned char>(c)) || std::string("-_./=:,+@%").find(c) != std::string::npos);
  if (plain) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::vector<std::string> taskArguments(const std::vector<std::string>& args) {
  // Options of the submission itself, and those every task sets anew: name -> takes a value.
  static const std::set<std::string> flags = {"--slurm", "--dry-run", "--quiet", "-q"};
  static const std::set<std::string> valued = {"--tasks", "--cpus-per-task", "--sbatch", "--jobs",
                                               "-j",      "--task",          "--of"};
  std::vector<std::string> out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const std::string name = a.substr(0, a.find('='));
    if (flags.count(a)) continue;
    if (valued.count(name)) {
      if (name == a) ++i;  // "--jobs 4": the value is the next word
      continue;
    }
    if (a.size() > 2 && a.rfind("-j", 0) == 0) continue;  // -j4
    out.push_back(a);
  }
  return out;
}

int submitStudy(const SlurmOptions& o, const std::vector<std::string>& args, const std::string& dir, int variants,
                bool quiet) {
  const int tasks = std::max(1, std::min(variants, o.tasks > 0 ? o.tasks : 100));
  std::error_code ec;
  const fs::path slurmDir = fs::absolute(fs::path(dir) / "slurm", ec);
  fs::create_directories(slurmDir, ec);
  const std::string cwd = fs::current_path(ec).string();
  const std::string self = selfPath();
  std::ostringstream common;
  common << "#SBATCH --chdir=" << shellQuote(cwd) << "\n";
  for (const auto& x : o.sbatch) common << "#SBATCH " << x << "\n";

  std::ostringstream study;
  study << "#!/bin/bash\n"
        << "# flexmb study as a Slurm job array, written by `flexmb study --slurm`. Task i of " << tasks
        << " runs variants\n"
        << "# i, i+" << tasks << ", ... (flexmb study --task i --of " << tasks
        << "); finished variants are skipped, so\n"
        << "# submitting this script again (sbatch " << (slurmDir / "study.sbatch").string() << ") resumes the study.\n"
        << "#SBATCH --job-name=flexmb-study\n"
        << "#SBATCH --array=0-" << tasks - 1 << "\n"
        << "#SBATCH --cpus-per-task=" << o.cpusPerTask << "\n"
        << "#SBATCH --output=" << shellQuote((slurmDir / "task-%A_%a.out").string()) << "\n"
        << common.str() << "exec " << shellQuote(self) << " study";
  for (const auto& a : taskArguments(args)) study << " " << shellQuote(a);
  study << " --task \"$SLURM_ARRAY_TASK_ID\" --of " << tasks << " --jobs \"${SLURM_CPUS_PER_TASK:-1}\" --quiet\n";

  std::ostringstream coll;
  coll << "#!/bin/bash\n"
       << "# Collects the study's summaries into study_summary.csv and study_report.html (written by\n"
       << "# `flexmb study --slurm`; submitted to start when the array has ended).\n"
       << "#SBATCH --job-name=flexmb-collect\n"
       << "#SBATCH --cpus-per-task=1\n"
       << "#SBATCH --output=" << shellQuote((slurmDir / "collect-%j.out").string()) << "\n"
       << common.str() << "exec " << shellQuote(self) << " study collect " << shellQuote(dir) << "\n";
  const std::string studyScript = (slurmDir / "study.sbatch").string(),
                    collectScript = (slurmDir / "collect.sbatch").string();
  try {
    writeScript(studyScript, study.str());
    writeScript(collectScript, coll.str());
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  if (!quiet) std::cout << "wrote " << studyScript << " (" << tasks << " array tasks) and " << collectScript << "\n";
  if (o.dryRun) {
    if (!quiet)
      std::cout << "submit with: jid=$(sbatch --parsable " << shellQuote(studyScript)
                << ") && sbatch --dependency=afterany:$jid " << shellQuote(collectScript) << "\n";
    return kOk;
  }
  bool ok = false;
  const std::string array = jobId(capture("sbatch --parsable " + shellQuote(studyScript), ok));
  if (!ok || array.empty()) {
    std::cerr << "flexmb: sbatch failed (is this a Slurm login node? `--dry-run` writes the scripts only)\n";
    return kInputError;
  }
  const std::string collectJob = jobId(capture(
      "sbatch --parsable --kill-on-invalid-dep=yes --dependency=afterany:" + array + " " + shellQuote(collectScript),
      ok));
  if (!ok || collectJob.empty()) {
    std::cerr << "flexmb: the array is job " << array << ", but sbatch refused the collect job; collect by hand "
              << "when it has ended: flexmb study collect " << dir << "\n";
    return kInputError;
  }
  std::cout << "submitted job array " << array << " (" << tasks << " tasks) and collect job " << collectJob
            << "\nfollow with: squeue -j " << array << "," << collectJob << "; the table: " << dir
            << "/study_summary.csv\n";
  return kOk;
}

}  // namespace flexmb::cli
