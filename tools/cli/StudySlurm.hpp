#pragma once
// `flexmb study --slurm`: the study as a Slurm job array (one task per share of the variants, each
// running `flexmb study ... --task $SLURM_ARRAY_TASK_ID --of N`) and a collect job that starts when
// the array has ended (afterany), written to <study>/slurm/ and submitted with sbatch (not with
// --dry-run).
#include <boost/program_options/options_description.hpp>
#include <string>
#include <vector>

namespace flexmb::cli {

struct SlurmOptions {
  bool submit = false;              // --slurm
  bool dryRun = false;              // --dry-run: write the scripts only
  int tasks = 0;                    // array tasks (0: min(variants, 100))
  int cpusPerTask = 1;              // each task runs --jobs $SLURM_CPUS_PER_TASK
  std::vector<std::string> sbatch;  // extra #SBATCH options (--time=..., --partition=...)
};

void addSlurmOptions(boost::program_options::options_description& d, SlurmOptions& o);

// The study's command line for one array task: args without the Slurm and job options, plus
// --task/--of/--jobs/--quiet. Exposed for the tests of the scripts.
std::vector<std::string> taskArguments(const std::vector<std::string>& args);
// A word for bash: single-quoted unless it is plain.
std::string shellQuote(const std::string& s);

// Writes <dir>/slurm/study.sbatch and collect.sbatch and submits them (unless o.dryRun); prints
// the job ids and how to follow them. Returns an exit code.
int submitStudy(const SlurmOptions& o, const std::vector<std::string>& args, const std::string& dir, int variants,
                bool quiet);

}  // namespace flexmb::cli
