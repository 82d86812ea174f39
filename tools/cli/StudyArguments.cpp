// flexmb study's options: parsing, the checks between them, and the analyses they choose.
#include <boost/program_options.hpp>
#include <iostream>

#include "tools/cli/StudyCommand.hpp"

namespace po = boost::program_options;

namespace flexmb::cli::study {

namespace {

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

}  // namespace

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
      "integrator", po::value(&sa.integrator), "simulate: auto (default), ode45, bdf or galpha (as flexmb simulate)")(
      "target", po::value(&sa.target)->notifier(finite("target")),
      "simulate: reduce each variant with the smallest modal basis whose reduction error estimate meets this "
      "target (0 < EPS < 1; columns sim_basis_vectors, sim_reduction_estimate)")(
      "derive", po::value(&sa.derive)->composing(),
      "a derived quantity name=expression in the parameters and quantities, e.g. "
      "stress=6*max_bending/(w*t^2) (repeatable)");
  po::options_description ed("the error against the converged model (measured at the first and last variant)");
  addAccuracyOptions(ed, sa.accuracy);
  ed.add_options()("reduce", po::bool_switch(&sa.reduce),
                   "with --accuracy and --simulate: reduce each variant with basis auto, its target a quarter of "
                   "EPS (the mesh gets half)");
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
  d.add(pd).add(ad).add(ed).add(rd).add(sd);
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
  if (sa.accuracy.asked() && sa.slurm.submit) {
    std::cerr << "flexmb: --accuracy and --error-estimate run their meshes before the variants, which --slurm "
                 "would do on the login node: submit the tasks yourself (--task i --of n; each measures the "
                 "same meshes)\n";
    return kUsageError;
  }
  if (sa.accuracy.estimate && sa.accuracy.eps > 0.0) {
    std::cerr << "flexmb: --accuracy estimates the error itself: give --accuracy or --error-estimate, not both\n";
    return kUsageError;
  }
  if (sa.reduce && !(sa.accuracy.eps > 0.0)) {
    std::cerr << "flexmb: --reduce goes with --accuracy (it splits EPS); without it, give --target\n";
    return kUsageError;
  }
  if (sa.accuracy.eps > 0.0 && !std::isnan(sa.target)) {
    std::cerr << "flexmb: --accuracy sets the reduction target itself (a quarter of EPS): give --reduce instead "
                 "of --target\n";
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
  if (sa.statics) {
    a.statics.emplace();
    a.statics->nev = sa.nev, a.statics->loadSteps = sa.steps, a.statics->buckling = sa.buckling;
  }
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
  } else if (!std::isnan(sa.target) || sa.reduce) {
    std::cerr << "flexmb: " << (sa.reduce ? "--reduce" : "--target") << " applies to --simulate\n";
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

}  // namespace flexmb::cli::study
