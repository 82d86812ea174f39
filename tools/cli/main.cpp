// flexmb: command-line front end. `flexmb <command> [options] model.dat` or SPACAR style
// `flexmb --mode N model.dat`. Exit codes (Commands.hpp, README): 0 done, 1 input error (file:line
// messages), 2 usage error, 3 numerical failure (time/coordinate and reason; results so far are
// written), 4 a result file could not be written, 130 interrupted (results so far are written).
#include <algorithm>
#include <cstring>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "io/formats/KeywordTable.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Visuals.hpp"

using namespace flexmb::cli;

namespace {
void usage(std::ostream& o) {
  o << "usage: flexmb <command> [options] model.dat\n"
       "       flexmb --mode N model.dat [options]     (SPACAR's modes: 0 check, 1 simulate, 3 linearised\n"
       "                                               matrices (trajectory or load steps), 4 eigenfrequencies\n"
       "                                               along the trajectory, 9 transfer, 10 static)\n\n"
       "commands:\n"
       "  check      mode 0: coordinates and deformations by role, degrees of freedom, rank check\n"
       "  show       the model as SVG: node and element numbers, roles (fixed, input, DOF)\n"
       "  simulate   mode 1: forward dynamics with the ode45-equivalent integrator;\n"
       "             --linearize N (mode 4) and --matrices (mode 3) linearise along the trajectory\n"
       "  modes      eigenfrequencies in the initial configuration\n"
       "  static     mode 10: equilibrium over the load steps, eigenfrequencies in each\n"
       "  transfer   mode 9: state-space model A, B, C, D of the last load step (transfer block), Bode diagrams\n"
       "  sweep      eigenfrequencies over a range of motion (one nodal coordinate prescribed)\n"
       "  reduce     build a modal or SVD-modal reduction basis (q = V eta)\n"
       "  study      a design study: a template model, a table of parameter values, the same analyses on\n"
       "             every variant on all cores (or Slurm), one table and report (`study collect`)\n"
       "  validate   reproduce the paper's Section 4 into validation/report/\n"
       "  keywords   list every .dat keyword flexmb reads\n"
       "Run `flexmb <command> --help` for a command's options; `flexmb --version` for the version.\n"
       "Exit codes: 0 done, 1 input error, 2 usage error, 3 numerical failure (results so far written),\n"
       "            4 a result file could not be written, 130 interrupted (results so far written).\n";
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help") {
    usage(args.empty() ? std::cerr : std::cout);
    return args.empty() ? kUsageError : kOk;
  }
  if (args[0] == "--version" || args[0] == "version") {
    // The release and the commit it was built from (git describe at configure time, tools/CMakeLists.txt).
    std::cout << "flexmb " << FLEXMB_VERSION << " (" << FLEXMB_COMMIT << ")\n";
    return kOk;
  }
  std::string command = args[0];
  args.erase(args.begin());
  if (command == "--mode" || command.rfind("--mode=", 0) == 0) {
    std::string n;
    if (command == "--mode") {
      if (args.empty()) {
        std::cerr << "flexmb: --mode needs a number\n";
        return kUsageError;
      }
      n = args[0];
      args.erase(args.begin());
    } else {
      n = command.substr(7);
    }
    static const std::map<std::string, std::string> modes = {
        {"0", "check"}, {"1", "simulate"}, {"3", "mode3"}, {"9", "transfer"}, {"10", "static"}};
    if (n == "4") args.push_back("--linearize=6");  // eigenfrequencies along the trajectory
    auto it = n == "4" ? modes.find("1") : modes.find(n);
    if (n == "8") {  // SPACAR's buckling mode: flexmb computes it with the static load steps
      std::cerr << "flexmb: mode 8 (buckling load factors) is part of the static analysis here: flexmb static "
                   "--buckling N model.dat gives the N lowest factors mu of (K0 + mu G0) v = 0 at every load step\n";
      return kUsageError;
    }
    if (n == "2") {  // named by SPACAR's help of 2001, defined nowhere public (docs/frontends/octave.md)
      std::cerr << "flexmb: mode 2 (SPACAR's inverse dynamic analysis with setpoint generation) is not supported: "
                   "no public source says how its setpoint is given or what it writes; the inverse dynamics of a "
                   "driven rigid mechanism (no degrees of freedom, moving inputs) is mode 1 (flexmb simulate)\n";
      return kUsageError;
    }
    if (it == modes.end()) {
      std::cerr << "flexmb: mode " << n
                << " is not supported (supported: 0, 1, 3, 4, 9, 10; buckling, SPACAR's mode "
                   "8: static --buckling N)\n";
      return kUsageError;
    }
    command = it->second;
    // SPACAR's modes of a run (1, 4, and 3 on a trajectory) write SPACAR's files by default, as
    // SPACAR does; `simulate` alone writes the CSV tables (its --format default).
    const bool formatGiven = std::any_of(
        args.begin(), args.end(), [](const std::string& a) { return a == "--format" || a.rfind("--format=", 0) == 0; });
    if ((command == "simulate" || command == "mode3") && !formatGiven) args.push_back("--format=both");
  }
  static const std::map<std::string, int (*)(const std::vector<std::string>&)> commands = {
      {"check", runCheck},   {"simulate", runSimulate}, {"keywords", runKeywords}, {"modes", runModes},
      {"static", runStatic}, {"sweep", runSweep},       {"reduce", runReduce},     {"validate", runValidate},
      {"show", runShow},     {"study", runStudy},       {"transfer", runTransfer}, {"mode3", runMode3}};
  auto it = commands.find(command);
  if (it == commands.end()) {
    // The nearest command within two edits (a typo: `simulat`, `chekc`), as the .dat reader
    // suggests keywords.
    std::string nearest;
    int best = 3;
    for (const auto& [name, run] : commands)
      if (const int dist = flexmb::io::editDistance(command, name); dist < best) best = dist, nearest = name;
    std::cerr << "flexmb: unknown command '" << command << "'"
              << (nearest.empty() ? std::string() : "; did you mean " + nearest + "?") << "\n";
    usage(std::cerr);
    return kUsageError;
  }
  try {
    return it->second(args);
  } catch (const std::bad_alloc&) {
    std::cerr << "flexmb: out of memory: the run is too large for this machine (fewer output intervals, a "
                 "reduced model or a shorter run)\n";
    return kNumericalFailure;
  } catch (const std::exception& e) {  // a safety net: every known failure is reported where it happens
    std::cerr << "flexmb: " << e.what() << "\n";
    return kInputError;
  }
}
