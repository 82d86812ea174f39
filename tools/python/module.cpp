// flexmb._core: the Python front end's native part (pybind11). It only dispatches: models come from
// io's reader, results from analysis's recipes, files from the writers the command line uses. The
// Python package (tools/python/flexmb/__init__.py) adds the keyword checks and the documentation.
//
// Results own their arrays (row-major, one row per step or output time, model order as the command
// line's CSV tables) and hand them to NumPy as read-only views, without copies. Analyses run with
// the GIL released; a Python user function takes it back for its call only.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>

#include "analysis/AccuracyTarget.hpp"
#include "analysis/BasisForTarget.hpp"
#include "analysis/InverseDynamics.hpp"
#include "analysis/ModelCheck.hpp"
#include "analysis/Modes.hpp"
#include "analysis/ModesJob.hpp"
#include "analysis/OperatorPolicy.hpp"
#include "analysis/Participation.hpp"
#include "analysis/ReduceJob.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/ReductionFiles.hpp"
#include "analysis/RunSize.hpp"
#include "analysis/SimulateJob.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/SimulationFiles.hpp"
#include "analysis/SpacarOutput.hpp"
#include "analysis/StaticDesign.hpp"
#include "analysis/StaticJob.hpp"
#include "analysis/Statics.hpp"
#include "analysis/StudyAccuracy.hpp"
#include "analysis/Sweep.hpp"
#include "analysis/SweepJob.hpp"
#include "analysis/Transfer.hpp"
#include "analysis/TransferFiles.hpp"
#include "analysis/TransferJob.hpp"
#include "core/model/UserFunctions.hpp"
#include "io/formats/BasisFile.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/MeshRefinement.hpp"
#include "io/formats/OperatorFile.hpp"
#include "io/formats/OutputFile.hpp"
#include "io/formats/TextOutput.hpp"
#include "io/pictures/DesignPlots.hpp"
#include "io/pictures/SvgPlot.hpp"
#include "io/templates/ModelTemplate.hpp"
#include "validation/PaperValidation.hpp"

namespace py = pybind11;
using namespace flexmb;

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ModelPtr = std::shared_ptr<const core::Model>;

// A model as read: every analysis stage of the file (SPACAR95 blocks), the last one the model the
// analyses without stages use, as the command line does.
struct ModelHandle {
  std::shared_ptr<const std::vector<io::AnalysisStage>> stages;
  ModelPtr last() const { return ModelPtr(stages, &stages->back().model); }
  const core::Model& operator*() const { return stages->back().model; }
  const core::Model* operator->() const { return &stages->back().model; }
};

// ---- Ctrl-C: a SIGINT handler of our own while an analysis runs in the main thread ----------------
std::atomic<bool> g_interrupt{false};
std::atomic<int> g_signal{0};
extern "C" void onSigint(int sig) {
  g_signal.store(sig);
  g_interrupt.store(true);
}

// Installs the handler for its lifetime when called from Python's main thread (Python runs signal
// handlers there only; other threads' analyses are not interruptible by Ctrl-C).
class InterruptScope {
 public:
  InterruptScope() {
    const py::object threading = py::module_::import("threading");
    active_ = threading.attr("current_thread")().is(threading.attr("main_thread")());
    if (!active_) return;
    g_interrupt.store(false);
    g_signal.store(0);
    struct sigaction sa {};
    sa.sa_handler = onSigint;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_);
  }
  ~InterruptScope() {
    if (active_) sigaction(SIGINT, &old_, nullptr);
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
  const std::atomic<bool>* flag() const { return active_ ? &g_interrupt : nullptr; }
  const std::atomic<int>* signal() const { return active_ ? &g_signal : nullptr; }
  bool interrupted() const { return active_ && g_interrupt.load(); }

 private:
  bool active_ = false;
  struct sigaction old_ {};
};

// Raises exception type `type` (a flexmb exception class or KeyboardInterrupt) with `message` and the
// result so far as its attribute `result`.
[[noreturn]] void raiseWithResult(py::handle type, const std::string& message, py::object result) {
  py::object exc = type(message);
  exc.attr("result") = std::move(result);
  PyErr_SetObject(type.ptr(), exc.ptr());
  throw py::error_already_set();
}

py::object package() { return py::module_::import("flexmb"); }

// ---- models ---------------------------------------------------------------------------------------
// f(), with io::DatError as flexmb.InputError(message, file, line, reason) and io::TemplateError
// as InputError(message, line).
template <class F>
auto asInputError(F&& f) {
  try {
    return f();
  } catch (const io::DatError& e) {
    py::object exc = package().attr("InputError")(e.what());
    exc.attr("file") = e.file();
    exc.attr("line") = e.line();
    exc.attr("reason") = e.message();
    PyErr_SetObject(package().attr("InputError").ptr(), exc.ptr());
    throw py::error_already_set();
  } catch (const io::TemplateError& e) {
    py::object exc = package().attr("InputError")(e.what());
    exc.attr("line") = e.line();
    PyErr_SetObject(package().attr("InputError").ptr(), exc.ptr());
    throw py::error_already_set();
  }
}

template <class F>
ModelHandle readModel(F&& read) {
  return asInputError([&] { return ModelHandle{std::make_shared<const std::vector<io::AnalysisStage>>(read())}; });
}

// The file's elements, without the normalisation constraints flexmb adds (as `flexmb show` counts).
std::size_t userElements(const core::Model& m) {
  std::size_t n = 0;
  for (const auto& el : m.elements) n += !(el.type && el.type->internal);
  return n;
}

py::list elementList(const core::Model& m) {
  py::list out;
  for (const auto& el : m.elements) {
    if (el.type && el.type->internal) continue;  // the normalisation constraints flexmb adds (L2MIN1)
    py::list nodes;
    for (int n : el.nodes) nodes.append(m.nodes[n].label);
    py::dict d;
    d["number"] = el.label;
    d["type"] = el.type ? el.type->keyword : std::string("?");
    d["nodes"] = nodes;
    out.append(d);
  }
  return out;
}

// ---- user functions -------------------------------------------------------------------------------
// USERSIG as a Python callable: f(t, x, xd, e, ed) returns sig (ne stresses added to the model's) or
// (sig, f) with f the nx nodal forces; None for either: zero. The arguments are read-only views on
// buffers reused from call to call (no allocation per call); model order, as the results.
class PythonStresses : public core::UserFunctions {
 public:
  PythonStresses(py::function f, const core::Model& model) : f_(std::move(f)), ne_(model.ne), nx_(model.nx) {
    x_.resize(nx_), xd_.resize(nx_), e_.resize(ne_), ed_.resize(ne_);
    auto view = [this](Eigen::VectorXd& v) {
      py::array a(py::dtype::of<double>(), {v.size()}, {sizeof(double)}, v.data(), py::none());
      py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
      return a;
    };
    vx_ = view(x_), vxd_ = view(xd_), ve_ = view(e_), ved_ = view(ed_);
  }
  ~PythonStresses() override {
    py::gil_scoped_acquire gil;
    f_ = py::function();
    vx_ = vxd_ = ve_ = ved_ = py::array();
  }
  bool hasLoads() const override { return true; }
  void loads(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::VectorXd& e,
             const Eigen::VectorXd& ed, Eigen::VectorXd& sigma, Eigen::VectorXd& f) override {
    sigma.setZero(ne_);
    f.setZero(nx_);
    py::gil_scoped_acquire gil;
    x_ = x, xd_ = xd, e_ = e, ed_ = ed;
    try {
      const py::object r = f_(t, vx_, vxd_, ve_, ved_);
      if (py::isinstance<py::tuple>(r)) {
        const py::tuple tup = r.cast<py::tuple>();
        if (tup.size() != 2)
          throw core::UserFunctionError(what(t) + " returned a tuple of " + std::to_string(tup.size()) +
                                        " items: expected sig (" + std::to_string(ne_) + ",) or (sig, f) with f (" +
                                        std::to_string(nx_) + ",)");
        take(tup[0], sigma, ne_, "sig", t);
        take(tup[1], f, nx_, "f", t);
      } else {
        take(r, sigma, ne_, "sig", t);
      }
    } catch (py::error_already_set& err) {
      const std::string trace = formatted(err);
      throw core::UserFunctionError(what(t) + " raised " + trace);
    } catch (const py::cast_error& err) {
      throw core::UserFunctionError(what(t) + ": " + err.what());
    }
  }

 private:
  static std::string what(double t) {
    std::ostringstream s;
    s.precision(10);
    s << "the Python USERSIG function at t = " << t;
    return s.str();
  }

 public:
  // The exception with its Python traceback, as Python prints it.
  static std::string formatted(py::error_already_set& err) {
    try {
      const py::object tb = py::module_::import("traceback");
      const py::list lines = tb.attr("format_exception")(err.type(), err.value(), err.trace());
      std::string s;
      for (const auto& l : lines) s += l.cast<std::string>();
      return s;
    } catch (...) {
      return err.what();
    }
  }

 private:
  static void take(const py::handle& h, Eigen::VectorXd& out, int n, const char* name, double t) {
    if (h.is_none()) return;
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
    if (!a || a.ndim() != 1 || a.shape(0) != n) {
      std::string got = a ? "shape (" : "a " + std::string(py::str(h.get_type().attr("__name__")));
      if (a) {
        for (py::ssize_t i = 0; i < a.ndim(); ++i) got += (i ? ", " : "") + std::to_string(a.shape(i));
        got += a.ndim() == 1 ? ",)" : ")";
      }
      throw core::UserFunctionError(what(t) + " returned " + name + " of " + got + ": expected shape (" +
                                    std::to_string(n) + ",)");
    }
    std::memcpy(out.data(), a.data(), sizeof(double) * n);
  }
  py::function f_;
  int ne_, nx_;
  Eigen::VectorXd x_, xd_, e_, ed_;
  py::array vx_, vxd_, ve_, ved_;
};

// USERINP as a Python callable: f(t, order) returns one value per input (Model.inputs: the
// prescribed coordinates, then the prescribed deformations) of that order (0 values, 1 rates,
// 2 accelerations). The kinematics ask for every input at one t and order: one call serves them.
class PythonInputs {
 public:
  PythonInputs(py::function f, int n) : f_(std::move(f)), values_(Eigen::VectorXd::Zero(n)) {}
  ~PythonInputs() {
    py::gil_scoped_acquire gil;
    f_ = py::function();
  }
  PythonInputs(const PythonInputs&) = delete;
  PythonInputs& operator=(const PythonInputs&) = delete;
  double at(double t, int order, int slot) {
    if (t != t_ || order != order_) {
      py::gil_scoped_acquire gil;
      const Eigen::Index n = values_.size();
      try {
        const py::object r = f_(t, order);
        const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(r);
        if (!a || a.ndim() != 1 || a.shape(0) != n)
          throw core::UserFunctionError(what(t, order) + " returned " +
                                        (a ? "an array of " + std::to_string(a.size()) + " values"
                                           : "a " + std::string(py::str(r.get_type().attr("__name__")))) +
                                        ": expected shape (" + std::to_string(n) + ",), one value per input");
        std::memcpy(values_.data(), a.data(), sizeof(double) * n);
      } catch (py::error_already_set& err) {
        throw core::UserFunctionError(what(t, order) + " raised " + PythonStresses::formatted(err));
      }
      t_ = t, order_ = order;
    }
    return values_[slot];
  }

 private:
  static std::string what(double t, int order) {
    std::ostringstream s;
    s.precision(10);
    s << "the Python USERINP function at t = " << t << " (order " << order << ")";
    return s.str();
  }
  py::function f_;
  Eigen::VectorXd values_;
  double t_ = NAN;
  int order_ = -1;
};

class PythonInputChannel : public core::TimeFunction {
 public:
  PythonInputChannel(std::shared_ptr<PythonInputs> source, int order, int slot)
      : source_(std::move(source)), order_(order), slot_(slot) {}
  double value(double t) const override { return source_->at(t, order_, slot_); }
  std::string text() const override { return "Python USERINP, input " + std::to_string(slot_ + 1); }

 private:
  std::shared_ptr<PythonInputs> source_;
  int order_, slot_;
};

// The model's inputs driven by f (their polynomials and expressions replaced).
void installInputs(const py::function& f, core::Model& model) {
  const int n = static_cast<int>(model.inputX.size() + model.inputE.size());
  auto source = std::make_shared<PythonInputs>(f, n);
  int slot = 0;
  for (auto* inputs : {&model.inputX, &model.inputE})
    for (auto& r : *inputs) {
      r.fx = std::make_shared<PythonInputChannel>(source, 0, slot);
      r.fv = std::make_shared<PythonInputChannel>(source, 1, slot);
      r.fa = std::make_shared<PythonInputChannel>(source, 2, slot);
      ++slot;
    }
}

// ---- results --------------------------------------------------------------------------------------
struct StaticResult {
  ModelPtr model;
  analysis::Diagnostics diagnostics;
  std::optional<analysis::ErrorBudget> budget;  // accuracy= / error_estimate=
  int refine = 1;
  double order = std::nan("");
  analysis::StaticRun run;
  int buckling = 0;
  Eigen::VectorXd loadFactor, initialFactor;
  RowMatrix x, e, sig, freq, bucklingFactors;
  analysis::StaticCompliances compliances;  // per step, the named nodes' (analysis/StaticDesign.hpp)
};

// Rows of a matrix from per-step vectors (NaN where a step has fewer).
template <class Steps, class Get>
RowMatrix rowsOf(const Steps& steps, int cols, Get get) {
  RowMatrix m = RowMatrix::Constant(static_cast<Eigen::Index>(steps.size()), cols, NAN);
  for (size_t k = 0; k < steps.size(); ++k) {
    const Eigen::VectorXd v = get(steps[k]);
    for (Eigen::Index j = 0; j < std::min<Eigen::Index>(cols, v.size()); ++j) m(static_cast<Eigen::Index>(k), j) = v[j];
  }
  return m;
}

StaticResult makeStatic(ModelPtr model, analysis::StaticRun run, int nev, int buckling) {
  StaticResult r;
  const auto& s = run.steps;
  r.loadFactor.resize(static_cast<Eigen::Index>(s.size()));
  r.initialFactor.resize(static_cast<Eigen::Index>(s.size()));
  for (size_t k = 0; k < s.size(); ++k) r.loadFactor[k] = s[k].loadFactor, r.initialFactor[k] = s[k].initialFactor;
  r.x = rowsOf(s, model->nx, [](const auto& st) { return st.x; });
  r.e = rowsOf(s, model->ne, [](const auto& st) { return st.e; });
  r.sig = rowsOf(s, model->ne, [](const auto& st) { return st.sigma; });
  r.freq = rowsOf(s, nev, [](const auto& st) { return Eigen::VectorXd(st.frequencies.omega / (2 * M_PI)); });
  r.bucklingFactors = rowsOf(s, buckling, [](const auto& st) { return st.buckling; });
  r.model = std::move(model);
  r.run = std::move(run);
  r.buckling = buckling;
  return r;
}

struct ModesResult {
  ModelPtr model;
  analysis::Diagnostics diagnostics;
  std::optional<analysis::ErrorBudget> budget;  // accuracy= / error_estimate=
  int refine = 1;
  double order = std::nan("");
  analysis::InitialModes modes;
  Eigen::VectorXd freq;  // Hz
  Eigen::VectorXd zeta;  // damping ratio per mode (empty: undamped)
};

struct SweepResultPy {
  std::optional<analysis::ErrorBudget> budget;  // accuracy= / error_estimate=
  int refine = 1;
  double order = std::nan("");
  ModelPtr model;
  analysis::Diagnostics diagnostics;
  analysis::SweepResult sweep;
  Eigen::VectorXd values, loads;
  RowMatrix freq, x;  // Hz ascending per point; nodal coordinates per point
};

struct TransferResultPy {
  ModelPtr model;
  analysis::Diagnostics diagnostics;
  analysis::TransferRun run;
};

struct ReduceResult {
  ModelPtr model;
  analysis::Diagnostics diagnostics;
  analysis::ReductionResult basis;
  analysis::BasisOperators operators;            // its reduced operators, or why there are none
  std::vector<analysis::TargetCandidate> tried;  // target: the candidates, smallest first
  bool full = false;                             // target: no basis smaller than the full model meets it
  std::string note;
};

// error_estimate= / accuracy= (analysis/AccuracyTarget.hpp): the request (None: neither asked).
std::optional<analysis::AccuracyRequest> accuracyAsked(bool estimate, double accuracy, double maxSeconds) {
  if (!estimate && !(accuracy > 0.0)) return std::nullopt;
  analysis::AccuracyRequest a;
  if (accuracy > 0.0) a.eps = accuracy;
  a.maxSeconds = maxSeconds;
  return a;
}

// A result's .error_estimate: the budget of --accuracy / --error-estimate (None: not asked).
py::object budgetOf(const std::optional<analysis::ErrorBudget>& b, int refine, double order) {
  if (!b) return py::none();
  py::dict d;
  d["estimated"] = b->estimated;
  d["total"] = b->total, d["discretization"] = b->discretization, d["reduction"] = b->reduction;
  d["integration"] = b->integration, d["met"] = b->met, d["refine"] = refine;
  d["observed_order"] = std::isnan(order) ? py::object(py::none()) : py::object(py::float_(order));
  d["seconds"] = b->seconds;
  py::dict settings;
  for (const auto& [k, v] : b->settings) settings[py::str(k)] = v;
  d["settings"] = settings;
  return d;
}

// What the ladder of accuracy= / error_estimate= leaves a result besides its job.
struct LadderKept {
  std::optional<analysis::ErrorBudget> budget;
  int refine = 1;
  double order = std::nan("");
  analysis::Diagnostics said;
  template <class Result>
  void into(Result& r) const {
    r.diagnostics.insert(r.diagnostics.end(), said.begin(), said.end());
    r.budget = budget, r.refine = refine, r.order = order;
  }
};

// The analysis's job: the ladder's answer (already run, GIL released) when asked, else a new one.
template <class Job, class Ladder, class Options>
std::unique_ptr<Job> jobOrLadder(const std::optional<analysis::AccuracyRequest>& ask, Ladder ladder,
                                 const analysis::ModelSource& source, Options options, LadderKept& kept) {
  if (!ask) return std::make_unique<Job>(source, std::move(options));
  analysis::AccurateRun<Job> run;
  {
    py::gil_scoped_release release;
    run = ladder(source, std::move(options), *ask);
  }
  kept.budget = run.budget, kept.refine = run.ladder.estimate.ofRefine;
  kept.order = run.ladder.estimate.observedOrder, kept.said = run.diagnostics;
  if (!run.job) throw py::value_error(analysis::firstError(run.diagnostics));
  return std::move(run.job);
}

// flexmb.simulate's options (the Python wrapper's keyword arguments, checked there).
struct SimulateOptionsPy {
  std::optional<double> tEnd, relTol, absTol, maxStep, rhoInf;
  std::optional<int> intervals;
  std::optional<std::string> integrator;  // None: the default (auto; ode45 with reduced operators)
  std::optional<Eigen::MatrixXd> basis;
  std::optional<std::string> basisFile;
  py::object reduced = py::none();  // a ReduceResult
  bool fullKinematics = false, accuracyCheck = false;
  std::optional<py::function> usersig, userinp;
  std::vector<double> dampingRatio;  // refused by the job (a time run), with why
  double alpha = 0.0, beta = 0.0;    // Rayleigh: beta K as element damping; alpha refused
  bool errorEstimate = false;        // error_estimate=: the discretization error of the model's mesh
  double accuracy = 0.0;             // accuracy=EPS (0: not asked)
  double maxSeconds = 300.0;
};

struct SimulationResult {
  ModelPtr model;
  analysis::Diagnostics diagnostics;            // what the run said (the command line's lines)
  std::optional<analysis::ErrorBudget> budget;  // accuracy= / error_estimate=
  int refine = 1;
  double order = std::nan("");
  analysis::SimulationOptions options;
  core::Trajectory trajectory;
  bool interrupted = false;
  Eigen::VectorXd time;
  RowMatrix x, xd, xdd, e, ed, edd, sig;
  RowMatrix fxt;                         // driven rigid mechanisms: the nodal forces per output time
  std::vector<Eigen::VectorXd> fxtRows;  // the same for the writer
};

SimulationResult makeSimulation(ModelPtr model, analysis::SimulationOptions opt, core::Trajectory traj,
                                bool interrupted) {
  SimulationResult r;
  const auto& s = traj.states;
  r.time = Eigen::Map<const Eigen::VectorXd>(traj.time.data(), static_cast<Eigen::Index>(traj.time.size()));
  r.x = rowsOf(s, model->nx, [](const auto& st) { return st.x; });
  r.xd = rowsOf(s, model->nx, [](const auto& st) { return st.xd; });
  r.xdd = rowsOf(s, model->nx, [](const auto& st) { return st.xdd; });
  r.e = rowsOf(s, model->ne, [](const auto& st) { return st.e; });
  r.ed = rowsOf(s, model->ne, [](const auto& st) { return st.ed; });
  r.edd = rowsOf(s, model->ne, [](const auto& st) { return st.edd; });
  r.sig = rowsOf(s, model->ne, [](const auto& st) { return st.sig; });
  opt.interrupt = nullptr;
  opt.interruptSignal = nullptr;
  r.model = std::move(model);
  r.options = std::move(opt);
  r.trajectory = std::move(traj);
  r.interrupted = interrupted;
  return r;
}

// A Python model as a job's source: its stages, read once when the model was read.
analysis::ModelSource sourceOf(const ModelHandle& h) { return {h->sourceFile, {}, h.stages, nullptr}; }

// An option of a diagnostic as Python spells it: the keyword argument.
std::string keyword(const std::string& name) { return name + "="; }

// A job refused before it ran: ValueError with the job's words (the same the command line prints).
void raiseIfRefused(const analysis::ModelJob& job) {
  if (job.status() == analysis::JobStatus::InputError)
    throw py::value_error(analysis::firstError(job.diagnostics(), keyword));
}

// A result's .messages: (kind, text) of what the job said, as the command line prints it beside the run.
std::vector<std::pair<std::string, std::string>> messagesOf(const analysis::Diagnostics& diagnostics) {
  static const char* kinds[] = {"result", "note", "warning", "error"};
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& d : diagnostics)
    out.emplace_back(kinds[static_cast<int>(d.kind)],
                     (d.where.empty() ? "" : d.where + ": ") + analysis::withOptions(d, keyword));
  return out;
}

// Writes a CSV table atomically (io::writeTextFile) and returns the path.
std::string writeTable(const std::string& path, const io::CsvTable& table) {
  io::writeTextFile(path, io::formatCsv(table));
  return path;
}

void bindModel(py::module_& m) {
  py::class_<ModelHandle>(m, "Model")
      .def(
          "refined",
          [](const ModelHandle& h, int parts,
             bool refinedResults) {  // every stage alike (io/formats/MeshRefinement.hpp)
            return asInputError([&] {
              auto stages = std::make_shared<std::vector<io::AnalysisStage>>(*h.stages);
              io::ReadOptions o;
              o.refine = parts;
              o.refinedResults = refinedResults;  // write(): every node, not the original ones
              io::refineStages(*stages, o);
              return ModelHandle{std::move(stages)};
            });
          },
          py::arg("parts"), py::kw_only(), py::arg("refined_results") = false)
      .def_property_readonly("file", [](const ModelHandle& h) { return h->sourceFile; })
      .def_property_readonly("nx", [](const ModelHandle& h) { return h->nx; })
      .def_property_readonly("ne", [](const ModelHandle& h) { return h->ne; })
      .def_property_readonly("ndof", [](const ModelHandle& h) { return h->numDofs(); })
      .def_property_readonly("spatial", [](const ModelHandle& h) { return h->spatial; })
      .def_property_readonly("nodes",
                             [](const ModelHandle& h) {
                               std::vector<int> labels;
                               for (const auto& n : h->nodes) labels.push_back(n.label);
                               return labels;
                             })
      .def_property_readonly("elements", [](const ModelHandle& h) { return elementList(*h); })
      .def_property_readonly("coordinates",
                             [](const ModelHandle& h) {
                               std::vector<std::string> names;
                               for (int i = 0; i < h->nx; ++i) names.push_back(h->coordName(i));
                               return names;
                             })
      .def_property_readonly("deformations",
                             [](const ModelHandle& h) {
                               std::vector<std::string> names;
                               for (int i = 0; i < h->ne; ++i) names.push_back(h->deformationName(i));
                               return names;
                             })
      .def_property_readonly("dofs",
                             [](const ModelHandle& h) {
                               std::vector<std::string> names;
                               for (const auto& d : h->dofs)
                                 names.push_back(d.isDeformation ? h->deformationName(d.index) : h->coordName(d.index));
                               return names;
                             })
      .def_property_readonly(
          "x0", [](const ModelHandle& h) -> const Eigen::VectorXd& { return h->x0; },
          py::return_value_policy::reference_internal)
      .def_property_readonly("notes", [](const ModelHandle& h) { return h->notes; })
      .def_property_readonly("warnings", [](const ModelHandle& h) { return h->warnings; })
      .def_property_readonly("inputs",
                             [](const ModelHandle& h) {
                               std::vector<std::string> names;
                               for (const auto& r : h->inputX) names.push_back(h->coordName(r.index));
                               for (const auto& r : h->inputE) names.push_back(h->deformationName(r.index));
                               return names;
                             })
      .def_property_readonly("stages", [](const ModelHandle& h) { return h.stages->size(); })
      .def("__repr__", [](const ModelHandle& h) {
        return "<flexmb.Model " + h->sourceFile + ": " + std::to_string(h->nodes.size()) + " nodes, " +
               std::to_string(userElements(*h)) + " elements, " + std::to_string(h->numDofs()) + " degrees of freedom>";
      });

  m.def(
      "read", [](const std::string& path) { return readModel([&] { return io::readDatStages(path); }); },
      py::arg("path"));
  m.def(
      "parse",
      [](const std::string& text, const std::string& name) {
        return readModel([&] { return io::readDatStagesString(text, name); });
      },
      py::arg("text"), py::arg("name"));
  m.def("instantiate", [](const std::string& text, const std::string& name, const io::ParameterValues& values) {
    return asInputError([&] {
      io::ModelTemplate t(text, name);
      std::vector<std::string> names;
      for (const auto& [k, v] : values) names.push_back(k);
      t.check(names);
      return t.instantiate(values);
    });
  });

  m.def("read_basis", [](const std::string& path, int dofs) {
    try {
      return io::readBasisFor(path, dofs);
    } catch (const std::exception& e) {
      throw py::value_error(std::string("basis: ") + e.what());
    }
  });
}

// `flexmb validate`: the paper's report into out_dir from the models in source_dir/datfiles;
// returns 0 (every acceptance check holds), 1 (one failed: the report says which) or 3 (an
// analysis stopped). Ctrl-C: KeyboardInterrupt, the previous report kept.
void bindValidate(py::module_& m) {
  m.def(
      "validate",
      [](const std::string& sourceDir, const std::string& outDir, int sweepSteps, bool quiet) {
        InterruptScope scope;
        validation::ValidationOptions o;
        o.sourceDir = sourceDir, o.outDir = outDir, o.sweepSteps = sweepSteps, o.quiet = quiet;
        o.interrupt = scope.flag(), o.interruptSignal = scope.signal();
        std::filesystem::create_directories(outDir);
        int rc = 0;
        {
          py::gil_scoped_release release;
          rc = validation::runValidation(o);
        }
        if (rc == validation::kInterrupted) {
          PyErr_SetString(PyExc_KeyboardInterrupt, "flexmb.validate: interrupted; the previous report is kept");
          throw py::error_already_set();
        }
        return rc;
      },
      py::arg("source"), py::arg("out"), py::arg("sweep_steps"), py::arg("quiet"));
}

void bindCheck(py::module_& m) {
  // ---- check (mode 0) ----
  m.def(
      "check",
      [](const ModelHandle& handle) {
        analysis::ModelCheck c;
        {
          py::gil_scoped_release release;
          c = analysis::checkModel(*handle);
        }
        py::dict d;
        d["well_posed"] = c.wellPosed();
        d["kinematics"] =
            c.kinematicsError.empty() ? c.kinematicsText() : "kinematic check failed: " + c.kinematicsError;
        d["mechanism_deformations"] = c.diagnosis.mechanismDeformations;
        d["overflow"] = c.diagnosis.overflow;
        d["assembly"] = c.assembly.problem.empty() ? c.assembly.error : c.assembly.problem;
        d["massless"] = c.assembly.massless;
        d["notes"] = handle->notes;
        d["warnings"] = handle->warnings;
        return d;
      },
      py::arg("model"));
  // SPACAR's mode 0 as SPACAR Light reads it from the .sbd (flexmb.light finds its releases from
  // it): D = de/dx in SPACAR's row and column order, le, nep and nxp.
  m.def(
      "kinematic",
      [](const ModelHandle& handle) {
        const io::SpacarLayout layout = io::spacarLayout(*handle);
        io::SpacarResults r;
        {
          py::gil_scoped_release release;
          r = analysis::spacarKinematic(*handle);
        }
        py::dict d;
        d["bigd"] = r.steps.empty() ? Eigen::MatrixXd() : r.steps.front().bigd;
        d["le"] = io::spacarTopology(*handle, layout).le;
        d["nep"] = std::vector<int>(layout.nep, layout.nep + 4);
        d["nxp"] = std::vector<int>(layout.nxp, layout.nxp + 4);
        return d;
      },
      py::arg("model"));
}

// flexmb.static: the static job (or the ladder of accuracy=), its result for Python.
StaticResult staticPy(const ModelHandle& handle, int nev, int loadSteps, int buckling,
                      const std::vector<int>& compliance, bool errorEstimate, double accuracy, double maxSeconds) {
  InterruptScope scope;
  analysis::StaticOptions so;
  so.nev = nev, so.loadSteps = loadSteps, so.buckling = buckling;
  so.complianceNodes = compliance;
  LadderKept kept;  // accuracy= / error_estimate= (analysis/AccuracyTarget.hpp)
  const auto owned = jobOrLadder<analysis::StaticJob>(accuracyAsked(errorEstimate, accuracy, maxSeconds),
                                                      &analysis::staticToAccuracy, sourceOf(handle), so, kept);
  analysis::StaticJob& job = *owned;
  raiseIfRefused(job);
  const ModelPtr model(job.allStages(), &job.model());
  {
    py::gil_scoped_release release;
    job.run({nullptr, scope.flag(), scope.signal()});
  }
  analysis::StaticRun run = job.result();
  StaticResult r = makeStatic(model, std::move(run), job.options().nev, buckling);
  r.compliances = job.compliances();
  r.diagnostics = job.diagnostics();
  kept.into(r);
  if (r.run.interrupted)
    raiseWithResult(PyExc_KeyboardInterrupt,
                    "flexmb.static: " + r.run.stopReason + "; the load steps reached are in .result",
                    py::cast(std::move(r)));
  return r;
}

void bindStatic(py::module_& m) {
  // ---- static ----
  py::class_<StaticResult>(m, "StaticResult")
      .def_property_readonly("messages", [](const StaticResult& r) { return messagesOf(r.diagnostics); })
      .def_property_readonly("error_estimate",
                             [](const StaticResult& r) { return budgetOf(r.budget, r.refine, r.order); })
      .def_readonly("load_factor", &StaticResult::loadFactor)
      .def_readonly("initial_factor", &StaticResult::initialFactor)
      .def_readonly("x", &StaticResult::x)
      .def_readonly("e", &StaticResult::e)
      .def_readonly("sig", &StaticResult::sig)
      .def_readonly("freq", &StaticResult::freq)
      .def_readonly("buckling", &StaticResult::bucklingFactors)
      .def_property_readonly("stable",
                             [](const StaticResult& r) {
                               std::vector<bool> v;
                               for (const auto& st : r.run.steps) v.push_back(st.newton.stable);
                               return v;
                             })
      .def_property_readonly("stability",
                             [](const StaticResult& r) {
                               std::vector<std::string> v;
                               for (const auto& st : r.run.steps) v.push_back(analysis::stabilityVerdict(st));
                               return v;
                             })
      .def_property_readonly("completed", [](const StaticResult& r) { return r.run.completed; })
      .def_property_readonly("stop_reason", [](const StaticResult& r) { return r.run.stopReason; })
      .def_property_readonly("load_step",
                             [](const StaticResult& r) {
                               std::vector<int> s;
                               for (const auto& st : r.run.steps) s.push_back(st.loadStep);
                               return s;
                             })
      .def_property_readonly("stress_elements",
                             [](const StaticResult& r) {
                               std::vector<int> labels;
                               for (int i : analysis::stressedElements(*r.model))
                                 labels.push_back(r.model->elements[static_cast<size_t>(i)].label);
                               return labels;
                             })
      .def_property_readonly("stress",
                             [](const StaticResult& r) {
                               const int n = static_cast<int>(analysis::stressedElements(*r.model).size());
                               return rowsOf(r.run.steps, n, [&](const auto& st) {
                                 const auto v = analysis::elementStresses(*r.model, st);
                                 Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
                                 for (size_t k = 0; k < v.size(); ++k)
                                   out[static_cast<Eigen::Index>(k)] = v[k].vonMises;
                                 return out;
                               });
                             })
      .def_property_readonly("stressmax",
                             [](const StaticResult& r) {
                               std::vector<double> v;
                               for (const auto& st : r.run.steps) {
                                 const auto top = analysis::largestStress(*r.model, st);
                                 v.push_back(top.element >= 0 ? top.vonMises : NAN);
                               }
                               return v;
                             })
      .def_property_readonly("reaction_names",
                             [](const StaticResult& r) {
                               std::vector<std::string> names;
                               for (const auto& [n, v] : analysis::supportReactions(*r.model, analysis::StaticStep()))
                                 names.push_back(n);
                               return names;
                             })
      .def_property_readonly(
          "reactions",
          [](const StaticResult& r) {
            const int n = static_cast<int>(analysis::supportReactions(*r.model, analysis::StaticStep()).size());
            return rowsOf(r.run.steps, n, [&](const auto& st) {
              const auto v = analysis::supportReactions(*r.model, st);
              Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
              for (size_t k = 0; k < v.size(); ++k) out[static_cast<Eigen::Index>(k)] = v[k].second;
              return out;
            });
          })
      .def_property_readonly("compliance",
                             [](const StaticResult& r) {
                               py::dict d;
                               for (const auto& step : r.compliances)
                                 for (const auto& nc : step) {
                                   const py::int_ key(nc.label);
                                   if (!d.contains(key)) d[key] = py::list();
                                   const Eigen::Index n = static_cast<Eigen::Index>(nc.names.size());
                                   d[key].cast<py::list>().append(nc.C.size() ? Eigen::MatrixXd(nc.C)
                                                                              : Eigen::MatrixXd::Constant(n, n, NAN));
                                 }
                               return d;
                             })
      .def_property_readonly("compliance_names",
                             [](const StaticResult& r) {
                               py::dict d;
                               if (!r.compliances.empty())
                                 for (const auto& nc : r.compliances.front()) d[py::int_(nc.label)] = nc.names;
                               return d;
                             })
      // plot: coordinates as the CSV names them; beside the CSV, <stem>_force_deflection.svg as
      // static --plot writes it (io/pictures/DesignPlots.hpp). An unknown name is a ValueError.
      // Returns the CSV's path, as before.
      .def(
          "write",
          [](const StaticResult& r, const std::string& path, const std::vector<std::string>& plot) {
            const io::CsvTable table = analysis::staticTable(*r.model, r.run, r.buckling);
            const auto panels =
                plot.empty()
                    ? std::vector<io::Plot>()
                    : io::staticForceDeflectionPlots(
                          *r.model, table, plot, r.model->sourceFile + ": load against deflection over the load steps");
            writeTable(path, table);
            if (panels.empty()) return path;
            const std::string stem = path.size() > 4 && path.compare(path.size() - 4, 4, ".csv") == 0
                                         ? path.substr(0, path.size() - 4)
                                         : path;
            const std::string svg = stem + "_force_deflection.svg";
            io::writeSvgStack(svg, panels);
            return path;
          },
          py::arg("path"), py::arg("plot") = std::vector<std::string>());
  m.def("static", &staticPy, py::arg("model"), py::arg("nev"), py::arg("load_steps"), py::arg("buckling"),
        py::arg("compliance"), py::arg("error_estimate"), py::arg("accuracy"), py::arg("max_seconds"));
}

void bindModes(py::module_& m) {
  // ---- modes ----
  py::class_<ModesResult>(m, "ModesResult")
      .def_property_readonly("messages", [](const ModesResult& r) { return messagesOf(r.diagnostics); })
      .def_property_readonly("error_estimate",
                             [](const ModesResult& r) { return budgetOf(r.budget, r.refine, r.order); })
      .def_readonly("freq", &ModesResult::freq)
      .def_property_readonly(
          "omega", [](const ModesResult& r) -> const Eigen::VectorXd& { return r.modes.frequencies.omega; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "modes", [](const ModesResult& r) -> const Eigen::MatrixXd& { return r.modes.frequencies.modes; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "modex", [](const ModesResult& r) -> const Eigen::MatrixXd& { return r.modes.frequencies.nodalModes; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "M0", [](const ModesResult& r) -> const Eigen::MatrixXd& { return r.modes.system.M; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "K0", [](const ModesResult& r) -> const Eigen::MatrixXd& { return r.modes.system.K; },
          py::return_value_policy::reference_internal)
      // The participation per global direction (analysis/Participation.hpp).
      .def_property_readonly("directions", [](const ModesResult& r) { return r.modes.participation.directions; })
      .def_property_readonly(
          "gamma", [](const ModesResult& r) -> const Eigen::MatrixXd& { return r.modes.participation.factors; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "meff", [](const ModesResult& r) -> const Eigen::MatrixXd& { return r.modes.participation.effective; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "meff_total", [](const ModesResult& r) -> const Eigen::VectorXd& { return r.modes.participation.total; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "rigid_body_mass",
          [](const ModesResult& r) -> const Eigen::MatrixXd& { return r.modes.participation.rigidBody; },
          py::return_value_policy::reference_internal)
      .def_readonly("zeta", &ModesResult::zeta)
      .def_property_readonly("mass", [](const ModesResult& r) { return r.modes.participation.mass(); })
      .def_property_readonly("centre_of_mass",
                             [](const ModesResult& r) { return r.modes.participation.centreOfMass(); })
      .def_property_readonly("reference", [](const ModesResult& r) { return r.modes.participation.reference; })
      .def("write", [](const ModesResult& r, const std::string& prefix) {
        std::vector<std::string> paths = {writeTable(prefix + "_modes.csv", analysis::modesTable(r.modes.frequencies))};
        if (!r.modes.participation.empty())
          paths.push_back(writeTable(prefix + "_participation.csv",
                                     analysis::participationTable(r.modes.frequencies.omega, r.modes.participation,
                                                                  r.zeta.size() ? &r.zeta : nullptr)));
        return paths;
      });
  m.def(
      "modes",
      [](const ModelHandle& handle, int nev, const std::optional<Eigen::MatrixXd>& basis,
         const Eigen::Vector3d& referencePoint, int referenceNode, const std::vector<double>& ratios, double alpha,
         double beta, bool errorEstimate, double accuracy, double maxSeconds) {
        ModesResult r;
        analysis::ModesOptions mo;
        mo.nev = nev;
        mo.basis.matrix = basis;
        mo.reference.point = referencePoint;
        mo.reference.node = referenceNode;
        mo.damping.ratios = ratios;
        mo.damping.alpha = alpha, mo.damping.beta = beta;
        LadderKept kept;  // accuracy= / error_estimate= (analysis/AccuracyTarget.hpp)
        const auto owned = jobOrLadder<analysis::ModesJob>(accuracyAsked(errorEstimate, accuracy, maxSeconds),
                                                           &analysis::modesToAccuracy, sourceOf(handle), mo, kept);
        analysis::ModesJob& job = *owned;
        raiseIfRefused(job);
        const ModelPtr model(job.allStages(), &job.model());
        {
          py::gil_scoped_release release;
          job.run();
        }
        if (job.status() != analysis::JobStatus::Completed)
          throw std::runtime_error(analysis::firstError(job.diagnostics()));
        r.modes = job.result();
        r.diagnostics = job.diagnostics();
        r.zeta = job.dampingRatios();
        kept.into(r);
        r.freq = r.modes.frequencies.omega / (2 * M_PI);
        r.model = model;
        return r;
      },
      py::arg("model"), py::arg("nev"), py::arg("basis"), py::arg("reference_point"), py::arg("reference_node"),
      py::arg("damping_ratio"), py::arg("alpha"), py::arg("beta"), py::arg("error_estimate"), py::arg("accuracy"),
      py::arg("max_seconds"));
}

void bindSweep(py::module_& m) {
  // ---- sweep ----
  py::class_<SweepResultPy>(m, "SweepResult")
      .def_property_readonly("messages", [](const SweepResultPy& r) { return messagesOf(r.diagnostics); })
      .def_property_readonly("error_estimate",
                             [](const SweepResultPy& r) { return budgetOf(r.budget, r.refine, r.order); })
      .def_readonly("values", &SweepResultPy::values)
      .def_readonly("loads", &SweepResultPy::loads)
      .def_readonly("freq", &SweepResultPy::freq)
      .def_readonly("x", &SweepResultPy::x)
      .def_property_readonly("prescribed", [](const SweepResultPy& r) { return r.sweep.prescribed; })
      .def_property_readonly("completed", [](const SweepResultPy& r) { return r.sweep.completed; })
      .def_property_readonly("stop_reason", [](const SweepResultPy& r) { return r.sweep.stopReason; })
      // The CSV's columns by name (max_stress, max_stress_element, the reactions R.*, ...; issue 53).
      .def_property_readonly("table",
                             [](const SweepResultPy& r) {
                               const io::CsvTable t = analysis::sweepTable(*r.model, r.sweep);
                               py::dict d;
                               for (size_t c = 0; c < t.columns.size(); ++c) {
                                 Eigen::VectorXd v(static_cast<Eigen::Index>(t.rows.size()));
                                 for (size_t k = 0; k < t.rows.size(); ++k)
                                   v[static_cast<Eigen::Index>(k)] = t.rows[k][c];
                                 d[py::str(t.columns[c])] = v;
                               }
                               return d;
                             })
      .def("write", [](const SweepResultPy& r, const std::string& path) {
        return writeTable(path, analysis::sweepTable(*r.model, r.sweep));
      });
  m.def(
      "sweep",
      [](const ModelHandle& handle, int node, int component, double from, double to, int steps, int nev,
         const std::optional<Eigen::MatrixXd>& basis, double t, bool errorEstimate, double accuracy,
         double maxSeconds) {
        InterruptScope scope;
        analysis::SweepOptions o;
        o.node = node, o.component = component, o.from = from, o.to = to, o.steps = steps, o.nev = nev, o.t = t;
        LadderKept kept;  // accuracy= / error_estimate= (analysis/AccuracyTarget.hpp)
        const auto ask = accuracyAsked(errorEstimate, accuracy, maxSeconds);
        const auto owned =
            ask ? jobOrLadder<analysis::SweepJob>(ask, &analysis::sweepToAccuracy, sourceOf(handle), o, kept)
                : std::make_unique<analysis::SweepJob>(sourceOf(handle), o, analysis::BasisInput{"", basis});
        analysis::SweepJob& job = *owned;
        raiseIfRefused(job);
        const ModelPtr model(job.allStages(), &job.model());
        SweepResultPy r;
        {
          py::gil_scoped_release release;
          job.run({nullptr, scope.flag(), scope.signal()});
        }
        raiseIfRefused(job);
        r.sweep = job.result();
        r.diagnostics = job.diagnostics();
        kept.into(r);
        nev = job.options().nev;
        const auto& p = r.sweep.points;
        r.values.resize(static_cast<Eigen::Index>(p.size()));
        r.loads.resize(static_cast<Eigen::Index>(p.size()));
        for (size_t k = 0; k < p.size(); ++k) r.values[k] = p[k].value, r.loads[k] = p[k].load;
        r.freq = rowsOf(p, nev, [](const auto& pt) { return Eigen::VectorXd(pt.omegaSorted / (2 * M_PI)); });
        r.x = rowsOf(p, model->nx, [](const auto& pt) { return pt.x; });
        r.model = model;
        if (r.sweep.interrupted)
          raiseWithResult(PyExc_KeyboardInterrupt,
                          "flexmb.sweep: " + r.sweep.stopReason + "; the points reached are in .result",
                          py::cast(std::move(r)));
        return r;
      },
      py::arg("model"), py::arg("node"), py::arg("component"), py::arg("start"), py::arg("stop"), py::arg("steps"),
      py::arg("nev"), py::arg("basis"), py::arg("t"), py::arg("error_estimate"), py::arg("accuracy"),
      py::arg("max_seconds"));
}

void bindTransfer(py::module_& m) {
  // ---- transfer ----
  py::class_<TransferResultPy>(m, "TransferResult")
      .def_property_readonly("messages", [](const TransferResultPy& r) { return messagesOf(r.diagnostics); })
      .def_property_readonly(
          "A", [](const TransferResultPy& r) -> const Eigen::MatrixXd& { return r.run.model.A; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "B", [](const TransferResultPy& r) -> const Eigen::MatrixXd& { return r.run.model.B; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "C", [](const TransferResultPy& r) -> const Eigen::MatrixXd& { return r.run.model.C; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "D", [](const TransferResultPy& r) -> const Eigen::MatrixXd& { return r.run.model.D; },
          py::return_value_policy::reference_internal)
      .def_property_readonly("inputs", [](const TransferResultPy& r) { return r.run.model.inputNames; })
      .def_property_readonly("outputs", [](const TransferResultPy& r) { return r.run.model.outputNames; })
      .def_property_readonly("completed", [](const TransferResultPy& r) { return r.run.completed; })
      .def_property_readonly("stop_reason", [](const TransferResultPy& r) { return r.run.stopReason; })
      .def("static_gain", [](const TransferResultPy& r) { return analysis::staticGain(r.run.model); })
      .def("frequency_response",
           [](const TransferResultPy& r, const Eigen::VectorXd& omega) {
             return analysis::frequencyResponses(r.run.model, omega);
           })
      .def("write", [](const TransferResultPy& r, const std::string& prefix, bool bode) {
        io::OutputSet files(prefix);
        files.checkWritable();
        files.setting("command", "transfer (Python)");
        files.setting("model", r.model->sourceFile);
        files.setting("load steps", std::to_string(r.run.statics.loadSteps));
        analysis::TransferFiles what;
        what.bode = bode;
        what.modelFile = r.model->sourceFile;
        std::ostringstream out, err;
        analysis::WrittenTransfer w;
        {
          py::gil_scoped_release release;
          w = analysis::writeTransfer(files, *r.model, r.run, what, out, err);
        }
        if (w.incomplete) py::module_::import("warnings").attr("warn")(err.str());
        return w.paths;
      });
  m.def(
      "transfer",
      [](const ModelHandle& handle, int nev, int loadSteps, const std::vector<double>& ratios, double alpha,
         double beta) {
        const ModelPtr model = handle.last();
        TransferResultPy r;
        analysis::TransferOptions o;
        o.nev = nev, o.loadSteps = loadSteps;
        o.damping.ratios = ratios;
        o.damping.alpha = alpha, o.damping.beta = beta;
        analysis::TransferJob job(sourceOf(handle), o);
        raiseIfRefused(job);
        {
          py::gil_scoped_release release;
          job.run();
        }
        if (job.status() == analysis::JobStatus::Failed)
          throw std::runtime_error(analysis::firstError(job.diagnostics()));
        r.run = job.result();
        r.diagnostics = job.diagnostics();
        r.model = model;
        return r;
      },
      py::arg("model"), py::arg("nev"), py::arg("load_steps"), py::arg("damping_ratio"), py::arg("alpha"),
      py::arg("beta"));
}

void bindReduce(py::module_& m) {
  // ---- reduce ----
  py::class_<ReduceResult>(m, "ReduceResult")
      .def_property_readonly("messages", [](const ReduceResult& r) { return messagesOf(r.diagnostics); })
      .def_property_readonly(
          "V", [](const ReduceResult& r) -> const Eigen::MatrixXd& { return r.basis.V; },
          py::return_value_policy::reference_internal)
      .def_property_readonly("method", [](const ReduceResult& r) { return r.basis.method; })
      .def_property_readonly("parameters", [](const ReduceResult& r) { return r.basis.parameters; })
      .def_property_readonly("large", [](const ReduceResult& r) { return r.basis.large; })
      .def_property_readonly("full", [](const ReduceResult& r) { return r.full; })
      .def_property_readonly("note", [](const ReduceResult& r) { return r.note; })
      .def_property_readonly("operators", [](const ReduceResult& r) { return r.operators.note; })
      .def_property_readonly("tried",
                             [](const ReduceResult& r) {
                               std::vector<std::pair<int, std::optional<double>>> out;
                               for (const auto& c : r.tried)
                                 out.emplace_back(c.vectors, c.estimate.estimated
                                                                 ? std::optional<double>(c.estimate.estimate)
                                                                 : std::nullopt);
                               return out;
                             })
      .def("write", [](const ReduceResult& r, const std::string& path) {
        if (r.full) throw py::value_error("no basis to write: " + r.note);
        io::OutputSet files(std::filesystem::path(path).replace_extension("").string());
        files.checkWritable();
        files.setting("command", "reduce (Python)");
        files.setting("model", r.model->sourceFile);
        analysis::writeReduction(files, path, r.model->sourceFile, r.basis, r.operators);
        return files.commit("complete");
      });
  m.def(
      "reduce",
      [](const ModelHandle& handle, const analysis::ReductionOptions& options, std::optional<double> target,
         bool operators, const std::vector<int>& trackNodes, const std::vector<int>& trackElements) {
        ReduceResult r;
        r.model = handle.last();
        analysis::ReduceOptions ro;
        ro.basis = options;
        if (target) ro.target = *target;
        ro.operators = operators;
        ro.trackNodes = trackNodes, ro.trackElements = trackElements;
        analysis::ReduceJob job(sourceOf(handle), ro);
        raiseIfRefused(job);
        {
          py::gil_scoped_release release;
          job.run();
          job.trainOperators();
        }
        raiseIfRefused(job);
        if (job.status() == analysis::JobStatus::Failed)
          throw std::runtime_error(analysis::firstError(job.diagnostics(), keyword));
        r.tried = job.target().tried;
        r.full = job.full();
        r.note = job.target().note;
        r.basis = job.basis();
        r.operators = job.operators();
        r.diagnostics = job.diagnostics();
        return r;
      },
      py::arg("model"), py::arg("options"), py::arg("target"), py::arg("operators"), py::arg("track_nodes"),
      py::arg("track_elements"));

  py::class_<analysis::ReductionOptions>(m, "ReductionOptions")
      .def(py::init<>())
      .def_readwrite("method", &analysis::ReductionOptions::method)
      .def_readwrite("modes", &analysis::ReductionOptions::modes)
      .def_readwrite("normalise", &analysis::ReductionOptions::normalise)
      .def_readwrite("large", &analysis::ReductionOptions::large)
      .def_readwrite("configs", &analysis::ReductionOptions::configs)
      .def_readwrite("weight", &analysis::ReductionOptions::weight)
      .def_readwrite("threshold", &analysis::ReductionOptions::threshold)
      .def_readwrite("count", &analysis::ReductionOptions::count)
      .def_readwrite("node", &analysis::ReductionOptions::node)
      .def_readwrite("component", &analysis::ReductionOptions::component)
      .def_readwrite("start", &analysis::ReductionOptions::from)
      .def_readwrite("stop", &analysis::ReductionOptions::to);
}

// flexmb.simulate: the simulate job (or the ladder of accuracy=), its result for Python.
SimulationResult simulatePy(const ModelHandle& handle, const SimulateOptionsPy& o) {
  analysis::SimulateRequest request;
  analysis::SimulationOptions& opt = request.run;
  const auto chosen = analysis::parseIntegrator(o.integrator.value_or("auto"));
  if (!chosen) throw py::value_error("integrator: 'ode45', 'bdf', 'auto' or 'galpha', not '" + *o.integrator + "'");
  opt.integrator = *chosen;
  request.defaultIntegrator = !o.integrator;
  if (o.rhoInf) opt.rhoInf = *o.rhoInf;
  opt.tEnd = o.tEnd, opt.relTol = o.relTol, opt.absTol = o.absTol, opt.maxStep = o.maxStep, opt.intervals = o.intervals;
  opt.accuracyCheck = o.accuracyCheck;
  request.basis = o.basis;
  request.fullKinematics = o.fullKinematics;
  request.damping.ratios = o.dampingRatio, request.damping.alpha = o.alpha, request.damping.beta = o.beta;
  if (o.basisFile) {
    request.basis.reset();
    request.basisFile = *o.basisFile;
  } else if (!o.reduced.is_none()) {
    const auto& reduced = o.reduced.cast<const ReduceResult&>();
    if (reduced.full) throw py::value_error("basis: the reduce result has no basis (" + reduced.note + ")");
    request.basis = reduced.basis.V;
    request.operators = reduced.operators.operators;
  }
  // The file's stages, with the Python user functions installed in a copy of them.
  std::shared_ptr<const std::vector<io::AnalysisStage>> stages = handle.stages;
  if (o.usersig || o.userinp) {
    auto copy = std::make_shared<std::vector<io::AnalysisStage>>(*handle.stages);
    for (auto& st : *copy) {
      if (o.usersig) st.model.userFunctions = std::make_shared<PythonStresses>(*o.usersig, st.model);
      if (o.userinp) installInputs(*o.userinp, st.model);
    }
    stages = copy;
  }
  InterruptScope scope;
  opt.interrupt = scope.flag(), opt.interruptSignal = scope.signal();
  const bool errorEstimate = o.errorEstimate;
  const double accuracy = o.accuracy, maxSeconds = o.maxSeconds;
  const analysis::ModelSource source{handle->sourceFile, {}, stages, nullptr};
  LadderKept kept;  // accuracy= / error_estimate= (analysis/AccuracyTarget.hpp)
  const auto owned =
      jobOrLadder<analysis::SimulateJob>(accuracyAsked(errorEstimate, accuracy, maxSeconds),
                                         &analysis::simulateToAccuracy, source, std::move(request), kept);
  analysis::SimulateJob& job = *owned;
  if (job.status() == analysis::JobStatus::InputError) {
    const std::string why = analysis::firstError(job.diagnostics(), keyword);
    throw py::value_error(job.driven() ? "basis: " + why : why);
  }
  {
    py::gil_scoped_release release;
    job.run();
  }
  if (job.status() == analysis::JobStatus::Failed) throw std::runtime_error(analysis::firstError(job.diagnostics()));
  const ModelPtr last(job.allStages(), &job.model());
  const std::string reason = job.trajectory().stopReason;
  const bool userFailed = !job.trajectory().completed && reason.find("the Python USER") != std::string::npos;
  SimulationResult r = makeSimulation(last, job.options(), std::move(job.trajectory()), job.interrupted());
  r.diagnostics = job.diagnostics();
  kept.into(r);
  r.fxtRows = job.fxt();
  r.fxt = rowsOf(r.fxtRows, r.fxtRows.empty() ? 0 : last->nx, [](const auto& v) { return v; });
  if (job.interrupted())
    raiseWithResult(PyExc_KeyboardInterrupt, "flexmb.simulate: " + reason + "; the results so far are in .result",
                    py::cast(std::move(r)));
  if (userFailed)
    raiseWithResult(package().attr("UserFunctionError"), "flexmb.simulate stopped: " + reason, py::cast(std::move(r)));
  return r;
}

void bindSimulate(py::module_& m) {
  // ---- simulate ----
  py::class_<SimulationResult>(m, "SimulationResult")
      .def_readonly("time", &SimulationResult::time)
      .def_readonly("x", &SimulationResult::x)
      .def_readonly("xd", &SimulationResult::xd)
      .def_readonly("xdd", &SimulationResult::xdd)
      .def_readonly("e", &SimulationResult::e)
      .def_readonly("ed", &SimulationResult::ed)
      .def_readonly("edd", &SimulationResult::edd)
      .def_readonly("sig", &SimulationResult::sig)
      .def_readonly("fxt", &SimulationResult::fxt)
      .def_property_readonly("completed", [](const SimulationResult& r) { return r.trajectory.completed; })
      .def_property_readonly("messages", [](const SimulationResult& r) { return messagesOf(r.diagnostics); })
      .def_property_readonly("error_estimate",
                             [](const SimulationResult& r) { return budgetOf(r.budget, r.refine, r.order); })
      .def_property_readonly("stop_reason", [](const SimulationResult& r) { return r.trajectory.stopReason; })
      .def_property_readonly("integrator", [](const SimulationResult& r) { return r.trajectory.integrator; })
      .def_property_readonly("nsteps", [](const SimulationResult& r) { return r.trajectory.nsteps; })
      .def_property_readonly("nfailed", [](const SimulationResult& r) { return r.trajectory.nfailed; })
      .def_property_readonly("nfevals", [](const SimulationResult& r) { return r.trajectory.nfevals; })
      .def_property_readonly(
          "statistics",
          [](const SimulationResult& r) { return analysis::formatStatistics(r.trajectory, r.options.integrator); })
      .def_property_readonly("reduced_dynamics",
                             [](const SimulationResult& r) -> std::string {
                               if (!r.options.basis) return "";
                               if (r.options.operators)
                                 return analysis::describeOperatorUse(r.trajectory.operators, *r.options.operators);
                               return "Eq. 19";
                             })
      .def_property_readonly("reduction_error_estimate",
                             [](const SimulationResult& r) -> std::optional<double> {
                               if (!r.trajectory.reduction.estimated) return std::nullopt;
                               return r.trajectory.reduction.estimate;
                             })
      .def("write", [](const SimulationResult& r, const std::string& prefix, bool csv, bool mat, int linearize,
                       bool matrices, bool vtk, bool html, const std::vector<std::string>& plot) {
        analysis::SimulationFiles what;
        what.csv = csv, what.mat = mat, what.linearize = linearize, what.matrices = matrices, what.vtk = vtk,
        what.html = html;
        what.plot = analysis::historyColumns(*r.model, plot);  // ValueError naming the names there are
        if (!r.fxtRows.empty()) what.fxt = &r.fxtRows;
        io::OutputSet files(prefix);
        files.checkWritable();
        files.setting("command", "simulate (Python)");
        files.setting("model", r.model->sourceFile);
        analysis::describeIntegration(files, *r.model, r.options);
        std::ostringstream out, err;
        analysis::WrittenSimulation w;
        {
          py::gil_scoped_release release;
          w = analysis::writeSimulation(files, *r.model, r.options, r.trajectory, r.interrupted, what, out, err);
        }
        if (w.incomplete) py::module_::import("warnings").attr("warn")(err.str());
        return w.paths;
      });
  // The options of flexmb.simulate, by name (help(flexmb._core.SimulateOptions) lists them); the
  // Python wrapper checks their types and fills them from its keyword arguments.
  py::class_<SimulateOptionsPy>(m, "SimulateOptions")
      .def(py::init<>())
      .def_readwrite("t_end", &SimulateOptionsPy::tEnd, "end time (default: the file's TIMESTEP)")
      .def_readwrite("reltol", &SimulateOptionsPy::relTol, "relative tolerance (default: the file's or 1e-3)")
      .def_readwrite("abstol", &SimulateOptionsPy::absTol, "absolute tolerance (default: the file's or 1e-6)")
      .def_readwrite("max_step", &SimulateOptionsPy::maxStep, "largest step")
      .def_readwrite("intervals", &SimulateOptionsPy::intervals, "output intervals (0: every step)")
      .def_readwrite("integrator", &SimulateOptionsPy::integrator,
                     "'auto', 'ode45', 'bdf' or 'galpha'; None: the default (auto; ode45 with reduced operators)")
      .def_readwrite("rho_inf", &SimulateOptionsPy::rhoInf, "galpha: the spectral radius at infinite step")
      .def_readwrite("basis", &SimulateOptionsPy::basis, "a basis matrix (ndof x k): Eq. 19")
      .def_readwrite("basis_file", &SimulateOptionsPy::basisFile, "a basis file of flexmb reduce")
      .def_readwrite("reduced", &SimulateOptionsPy::reduced, "a flexmb.reduce result (its basis and operators)")
      .def_readwrite("full_kinematics", &SimulateOptionsPy::fullKinematics, "Eq. 19 even where operators hold")
      .def_readwrite("usersig", &SimulateOptionsPy::usersig, "f(t, x, xd, e, ed) -> sig or (sig, f)")
      .def_readwrite("userinp", &SimulateOptionsPy::userinp, "f(t, order) -> one value per input")
      .def_readwrite("accuracy_check", &SimulateOptionsPy::accuracyCheck, "the a-posteriori accuracy check")
      .def_readwrite("damping_ratio", &SimulateOptionsPy::dampingRatio, "modal ratios (refused in a time run)")
      .def_readwrite("alpha", &SimulateOptionsPy::alpha, "Rayleigh's alpha (refused in a time run unless 0)")
      .def_readwrite("beta", &SimulateOptionsPy::beta, "Rayleigh's beta: beta K as element damping (EDAMP)")
      .def_readwrite("error_estimate", &SimulateOptionsPy::errorEstimate, "the discretization error of the mesh")
      .def_readwrite("accuracy", &SimulateOptionsPy::accuracy, "the total error target EPS (0: none)")
      .def_readwrite("max_seconds", &SimulateOptionsPy::maxSeconds, "accuracy=: the time allowed in all");
  m.def("simulate", &simulatePy, py::arg("model"), py::arg("options"));
}

// flexmb.study: the variants of a template run one after another in this process (`flexmb study`'s
// recipe, analysis/Study.hpp, without its folder and workers); accuracy= / error_estimate= measure the
// mesh on the first and the last variant first (analysis/StudyAccuracy.hpp).
py::dict studyPy(const std::string& text, const std::string& name, const std::vector<io::ParameterValues>& variants,
                 int modes, bool statics, int nev, bool simulate, std::optional<double> tEnd,
                 std::optional<double> relTol, int refine, bool errorEstimate, double accuracy, double maxSeconds,
                 bool reduce) {
  if (variants.empty()) throw py::value_error("variants: give at least one");
  analysis::StudyAnalyses a;
  a.modes = modes;
  if (statics) a.statics.emplace(), a.statics->nev = nev;
  if (simulate) {
    analysis::SimulationOptions o;
    o.tEnd = tEnd, o.relTol = relTol, o.keepStates = true;
    o.integrator = analysis::Integrator::Auto;  // `flexmb study`'s default, as flexmb.simulate's
    a.simulation = o;
  }
  const io::ModelTemplate t = asInputError([&] {
    io::ModelTemplate m(text, name);
    std::vector<std::string> names;
    for (const auto& [k, v] : variants.front()) names.push_back(k);
    m.check(names);
    return m;
  });
  io::ReadOptions read;
  read.refine = refine;
  py::dict out;
  out["accuracy"] = py::none();
  if (const auto ask = accuracyAsked(errorEstimate, accuracy, maxSeconds)) {
    std::vector<analysis::StudyEnd> ends;
    for (const io::ParameterValues* v : {&variants.front(), &variants.back()}) {
      if (!ends.empty() && variants.size() == 1) break;
      analysis::StudyEnd e;
      e.name = "variant " + std::to_string(ends.empty() ? 1 : variants.size());
      e.source.file = name, e.source.read = read;
      e.source.text = std::make_shared<const std::string>(asInputError([&] { return t.instantiate(*v); }));
      ends.push_back(std::move(e));
    }
    analysis::StudyAccuracyPlan plan;
    try {
      py::gil_scoped_release release;
      plan = analysis::planStudyAccuracy(ends, a, *ask, reduce);
    } catch (const std::invalid_argument& e) {
      throw py::value_error(e.what());
    }
    if (!plan.ok) throw py::value_error(analysis::firstError(plan.diagnostics));
    read.refine = a.accuracy->refine;
    py::dict settings;
    for (const auto& [k, v] : plan.settings)
      settings[py::str(k)] =
          settings.contains(k) ? py::str(settings[py::str(k)].cast<std::string>() + "; " + v) : py::str(v);
    out["accuracy"] = settings;
    out["messages"] = messagesOf(plan.diagnostics);
  }
  py::list rows;
  for (size_t k = 0; k < variants.size(); ++k) {
    io::ParameterValues names = variants[k];
    const std::string instantiated = asInputError([&] { return t.instantiate(variants[k], &names); });
    const core::Model model = asInputError([&] { return io::readDatString(instantiated, name, read); });
    analysis::VariantResults r;
    {
      py::gil_scoped_release release;
      r = analysis::runVariant(model, a, names);
    }
    py::dict row;
    for (const auto& [n, v] : variants[k]) row[py::str(n)] = v;
    for (const auto& [n, v] : r.quantities) row[py::str(n)] = std::isnan(v) ? py::object(py::none()) : py::float_(v);
    row["status"] = r.failure.empty() ? "ok" : "failed";
    row["reason"] = analysis::summaryRecord(analysis::Variant{static_cast<int>(k) + 1, "", variants[k]}, r).reason;
    rows.append(row);
  }
  out["variants"] = rows;
  return out;
}

void bindStudy(py::module_& m) {
  m.def("study", &studyPy, py::arg("text"), py::arg("name"), py::arg("variants"), py::arg("modes"), py::arg("static"),
        py::arg("nev"), py::arg("simulate"), py::arg("t_end"), py::arg("reltol"), py::arg("refine"),
        py::arg("error_estimate"), py::arg("accuracy"), py::arg("max_seconds"), py::arg("reduce"));
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "flexmb's native part; use the flexmb package";
  bindModel(m);
  bindCheck(m);
  bindValidate(m);
  bindStatic(m);
  bindModes(m);
  bindSweep(m);
  bindTransfer(m);
  bindReduce(m);
  bindSimulate(m);
  bindStudy(m);
}
