// Bdf: SUNDIALS CVODE 6.x (SUNContext API), BDF + Newton + SUNDenseMatrix/SUNLinSol_Dense.
#include "solvers/Bdf.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <utility>
#include "text/NumberText.hpp"

namespace flexmb::solvers {
namespace {

using text::shortest;

// The SUNDIALS objects of one run, released in the right order whatever happens.
struct Sundials {
  SUNContext ctx = nullptr;
  void* mem = nullptr;
  N_Vector y = nullptr, dky = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  Sundials() = default;
  Sundials(const Sundials&) = delete;
  Sundials& operator=(const Sundials&) = delete;
  ~Sundials() {
    if (mem) CVodeFree(&mem);
    if (LS) SUNLinSolFree(LS);
    if (A) SUNMatDestroy(A);
    if (dky) N_VDestroy(dky);
    if (y) N_VDestroy(y);
    if (ctx) SUNContext_Free(&ctx);
  }
};

// What the C callbacks see: the user's callables and preallocated buffers. Exceptions never cross
// CVODE's C frames: they become return codes (recoverable 1, unrecoverable -1) and are rethrown or
// reported after CVode returns.
struct Session {
  const OdeRhs* f = nullptr;
  const OdeJacobian* jac = nullptr;
  Eigen::VectorXd y, fy, dy;
  long calls = 0;
  std::string rhsError;    // last recoverable failure of f or J (with its time)
  std::string abortError;  // an RhsAbort: stop at once
  std::string cvodeError;  // CVODE's own last error message
  std::exception_ptr unexpected;

  void load(N_Vector v, Eigen::VectorXd& to) const { std::copy(NV_DATA_S(v), NV_DATA_S(v) + to.size(), to.data()); }
  // Runs fn, mapping exceptions to CVODE's return codes.
  template <class Fn>
  int guarded(double t, const char* what, Fn&& fn) {
    try {
      fn();
      return 0;
    } catch (const RhsAbort& e) {
      abortError = e.what();
      return -1;
    } catch (const RhsError& e) {
      rhsError = std::string(what) + " failed at t = " + text::shortest(t) + ": " + e.what();
      return 1;
    } catch (...) {
      unexpected = std::current_exception();
      return -1;
    }
  }
};

int rhsCallback(realtype t, N_Vector y, N_Vector ydot, void* data) {
  auto& s = *static_cast<Session*>(data);
  ++s.calls;
  s.load(y, s.y);
  if (!s.y.allFinite()) {
    s.rhsError = "right-hand side failed at t = " + text::shortest(t) + ": non-finite state y";
    return 1;
  }
  const int rc = s.guarded(t, "right-hand side", [&] { (*s.f)(t, s.y, s.dy); });
  if (rc != 0) return rc;
  if (s.dy.size() != s.y.size() || !s.dy.allFinite()) {
    s.rhsError = "right-hand side failed at t = " + text::shortest(t) + ": " +
                 (s.dy.size() != s.y.size() ? "wrong size of dydt" : "non-finite value in dydt");
    if (s.dy.size() != s.y.size()) s.dy.resize(s.y.size());
    return 1;
  }
  std::copy(s.dy.data(), s.dy.data() + s.dy.size(), NV_DATA_S(ydot));
  return 0;
}

int jacCallback(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void* data, N_Vector, N_Vector, N_Vector) {
  auto& s = *static_cast<Session*>(data);
  s.load(y, s.y);
  s.load(fy, s.fy);
  const Eigen::Index n = s.y.size();
  Eigen::Map<Eigen::MatrixXd> Jm(SM_DATA_D(J), n, n);  // column-major, leading dimension n
  const int rc = s.guarded(t, "Jacobian", [&] { (*s.jac)(t, s.y, s.fy, Jm); });
  if (rc != 0) return rc;
  if (!Jm.allFinite()) {
    s.rhsError = "Jacobian failed at t = " + text::shortest(t) + ": non-finite entry";
    return 1;
  }
  return 0;
}

void errorHandler(int code, const char* module, const char* function, char* msg, void* data) {
  if (code == CV_WARNING) return;  // "t + h = t" notes: the step-size failure that follows says it
  static_cast<Session*>(data)->cvodeError =
      std::string(module ? module : "CVODE") + "/" + (function ? function : "?") + ": " + (msg ? msg : "");
}

// CVODE's failure flags as statuses, with a sentence a user can act on.
std::pair<OdeStatus, std::string> describe(int flag) {
  switch (flag) {
    case CV_TOO_MUCH_ACC:
      return {OdeStatus::StepSizeUnderflow, "the tolerance is too small for the machine precision"};
    case CV_ERR_FAILURE:
      return {OdeStatus::StepSizeUnderflow,
              "the error test failed repeatedly or at the minimum step size: the tolerance cannot be met"};
    case CV_CONV_FAILURE:
      return {OdeStatus::ConvergenceFailure,
              "the Newton corrector did not converge, repeatedly or at the minimum step size"};
    case CV_LINIT_FAIL:
    case CV_LSETUP_FAIL:
    case CV_LSOLVE_FAIL:
      return {OdeStatus::JacobianFailed,
              "the Jacobian or the linear solver failed (singular iteration matrix or a failing Jacobian)"};
    case CV_RHSFUNC_FAIL:
    case CV_FIRST_RHSFUNC_ERR:
    case CV_REPTD_RHSFUNC_ERR:
    case CV_UNREC_RHSFUNC_ERR:
      return {OdeStatus::RhsFailed, "the right-hand side failed"};
    default: {
      char* name = CVodeGetReturnFlagName(flag);
      std::string text = std::string("CVODE returned ") + (name ? name : std::to_string(flag));
      std::free(name);
      return {OdeStatus::SolverFailure, text};
    }
  }
}

}  // namespace

Bdf::Bdf(BdfOptions options) : opt_(std::move(options)) {
  if (!(opt_.relTol > 0.0) || !std::isfinite(opt_.relTol)) throw std::invalid_argument("Bdf: relTol must be positive");
  if (!(opt_.absTol > 0.0) || !std::isfinite(opt_.absTol)) throw std::invalid_argument("Bdf: absTol must be positive");
  if (opt_.absTols.size() && !((opt_.absTols.array() > 0.0).all() && opt_.absTols.allFinite()))
    throw std::invalid_argument("Bdf: absTols must be positive");
  if (!(opt_.maxStep >= 0.0)) throw std::invalid_argument("Bdf: maxStep must be >= 0");
  if (!(opt_.initialStep >= 0.0)) throw std::invalid_argument("Bdf: initialStep must be >= 0");
  if (opt_.maxOrder < 1 || opt_.maxOrder > 5) throw std::invalid_argument("Bdf: maxOrder must be 1 ... 5");
}

std::string Bdf::library() { return std::string("SUNDIALS CVODE ") + SUNDIALS_VERSION; }

std::string Bdf::formatStats(const OdeStats& s) {
  std::string out = std::to_string(s.nsteps) + " successful steps\n" + std::to_string(s.nfailed) +
                    " failed attempts\n" + std::to_string(s.nfevals) + " function evaluations\n";
  if (s.njacfevals > 0) {  // appended piecewise: "(" + std::string trips GCC 12's -Wrestrict
    out += '(';
    out += std::to_string(s.njacfevals);
    out += " of them for difference-quotient Jacobians)\n";
  }
  out += std::to_string(s.njacevals) + " Jacobian evaluations\n" + std::to_string(s.nlinsetups) +
         " linear-solver set-ups\n";
  return out;
}

namespace {

// CVODE's settings: tolerances, dense linear solver (with the analytic Jacobian when given), order,
// step bounds and the stop time.
void configureCvode(Sundials& sd, Session& session, bool analyticJacobian, const BdfOptions& opt, double t0,
                    double tf) {
  const double tdir = tf > t0 ? 1.0 : -1.0;
  auto check = [](int flag, const char* what) {
    if (flag < 0)
      throw std::runtime_error(std::string("Bdf: CVODE set-up ") + what + " failed (" + std::to_string(flag) + ")");
  };
  const double span = std::fabs(tf - t0);
  const double hmax = opt.maxStep > 0.0 ? std::min(span, opt.maxStep) : 0.1 * span;
  // hmin as Ode45's 16 eps(t) (at the larger end): a step below it means the tolerance cannot be
  // met, instead of a crawl to h ~ 1e-19 through repeated failures.
  const double hmin = 16.0 * spacingOfDoublesAt(std::max(std::fabs(t0), std::fabs(tf)));
  check(CVodeSetErrHandlerFn(sd.mem, errorHandler, &session), "CVodeSetErrHandlerFn");
  check(CVodeInit(sd.mem, rhsCallback, t0, sd.y), "CVodeInit");
  if (opt.absTols.size()) {  // CVODE keeps a copy of the vector
    N_Vector a = N_VClone(sd.y);
    if (!a) throw std::runtime_error("Bdf: CVODE could not allocate its memory");
    std::copy(opt.absTols.data(), opt.absTols.data() + opt.absTols.size(), NV_DATA_S(a));
    const int flag = CVodeSVtolerances(sd.mem, opt.relTol, a);
    N_VDestroy(a);
    check(flag, "CVodeSVtolerances");
  } else {
    check(CVodeSStolerances(sd.mem, opt.relTol, opt.absTol), "CVodeSStolerances");
  }
  check(CVodeSetUserData(sd.mem, &session), "CVodeSetUserData");
  check(CVodeSetLinearSolver(sd.mem, sd.LS, sd.A), "CVodeSetLinearSolver");
  if (analyticJacobian) check(CVodeSetJacFn(sd.mem, jacCallback), "CVodeSetJacFn");  // else difference quotients
  check(CVodeSetMaxOrd(sd.mem, opt.maxOrder), "CVodeSetMaxOrd");
  check(CVodeSetMaxStep(sd.mem, hmax), "CVodeSetMaxStep");
  check(CVodeSetMinStep(sd.mem, std::min(hmin, 0.5 * hmax)), "CVodeSetMinStep");
  if (opt.initialStep > 0.0)
    check(CVodeSetInitStep(sd.mem, tdir * std::min(opt.initialStep, hmax)), "CVodeSetInitStep");
  check(CVodeSetStopTime(sd.mem, tf), "CVodeSetStopTime");
}

// The counts so far (every evaluation, difference-quotient Jacobians included).
void cvodeStats(void* mem, OdeStats& stats) {
  long nst = 0, nfe = 0, nfeLS = 0, netf = 0, ncfn = 0, nje = 0, nsetups = 0;
  CVodeGetNumSteps(mem, &nst);
  CVodeGetNumRhsEvals(mem, &nfe);
  CVodeGetNumLinRhsEvals(mem, &nfeLS);
  CVodeGetNumErrTestFails(mem, &netf);
  CVodeGetNumNonlinSolvConvFails(mem, &ncfn);
  CVodeGetNumJacEvals(mem, &nje);
  CVodeGetNumLinSolvSetups(mem, &nsetups);
  stats.nsteps = nst;
  stats.nfailed = netf + ncfn;  // error-test and corrector-convergence failures
  stats.nfevals = nfe + nfeLS;
  stats.njacfevals = nfeLS;
  stats.njacevals = nje;
  stats.nlinsetups = nsetups;
}

}  // namespace

OdeResult Bdf::integrate(const OdeRhs& f, const OdeJacobian& jacobian, const std::vector<double>& tspan,
                         const Eigen::VectorXd& y0, const OdeObserver& observer, const OdeStepHook& accepted) const {
  const Eigen::Index n = y0.size();
  const std::size_t ntspan = tspan.size();
  checkTimeSpan(tspan, "Bdf");
  const double t0 = tspan.front(), tf = tspan.back();
  const double tdir = tf > t0 ? 1.0 : -1.0;
  if (n == 0) throw std::invalid_argument("Bdf: empty state y0");
  if (!y0.allFinite()) throw std::invalid_argument("Bdf: y0 is not finite");
  if (opt_.absTols.size() && opt_.absTols.size() != n)
    throw std::invalid_argument("Bdf: absTols must hold one value per component of y0");

  OdeResult res;
  res.tLast = t0;
  auto fail = [&](OdeStatus s, std::string msg) {
    res.status = s;
    res.message = std::move(msg);
  };

  Session session;
  session.f = &f;
  session.jac = &jacobian;
  session.y.resize(n);
  session.fy.resize(n);
  session.dy.resize(n);

  Sundials sd;
  if (SUNContext_Create(nullptr, &sd.ctx) != 0) throw std::runtime_error("Bdf: SUNContext_Create failed");
  sd.y = N_VNew_Serial(static_cast<sunindextype>(n), sd.ctx);
  sd.dky = N_VNew_Serial(static_cast<sunindextype>(n), sd.ctx);
  sd.mem = CVodeCreate(CV_BDF, sd.ctx);
  sd.A = SUNDenseMatrix(static_cast<sunindextype>(n), static_cast<sunindextype>(n), sd.ctx);
  if (!sd.y || !sd.dky || !sd.mem || !sd.A) throw std::runtime_error("Bdf: CVODE could not allocate its memory");
  sd.LS = SUNLinSol_Dense(sd.y, sd.A, sd.ctx);
  if (!sd.LS) throw std::runtime_error("Bdf: SUNLinSol_Dense failed");
  std::copy(y0.data(), y0.data() + n, NV_DATA_S(sd.y));

  configureCvode(sd, session, static_cast<bool>(jacobian), opt_, t0, tf);
  auto collectStats = [&] { cvodeStats(sd.mem, res.stats); };

  if (!observer(t0, y0)) {
    fail(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(t0));
    return res;
  }
  Eigen::VectorXd y(n), yout(n);
  auto hook = [&](double t, const Eigen::VectorXd& state) {
    if (!accepted) return true;
    try {
      accepted(t, state);
    } catch (const RhsAbort& e) {  // a user function or Ctrl-C at an accepted state: stop, keep the results
      fail(OdeStatus::RhsFailed, std::string(e.what()) + " (at the accepted state t = " + text::shortest(t) + ")");
      return false;
    } catch (const RhsError& e) {
      fail(OdeStatus::RhsFailed, "BDF integration stopped at the accepted state t = " + text::shortest(t) + ": " +
                                     e.what() + "; results up to there are kept");
      return false;
    }
    return true;
  };
  if (!hook(t0, y0)) return res;

  const bool everyStep = ntspan == 2;
  std::size_t next = 1;
  while (true) {
    realtype tcur = t0;
    const int flag = CVode(sd.mem, tf, sd.y, &tcur, CV_ONE_STEP);
    if (session.unexpected) std::rethrow_exception(session.unexpected);
    if (flag < 0) {
      collectStats();
      auto [status, why] = describe(flag);
      std::string msg;
      if (!session.abortError.empty()) {
        status = OdeStatus::RhsFailed;
        msg = session.abortError + " (at t = " + text::shortest(tcur) + ")";
      } else {
        msg = "BDF integration stopped at t = " + text::shortest(tcur) + ": " + why;
        if (!session.cvodeError.empty()) msg += " (" + session.cvodeError + ")";
        if (!session.rhsError.empty()) msg += "; last failure: " + session.rhsError;
        msg += "; results up to there are kept";
      }
      fail(status, std::move(msg));
      return res;
    }
    res.tLast = tcur;
    session.load(sd.y, y);
    const bool done = flag == CV_TSTOP_RETURN || tdir * (tcur - tf) >= 0.0;
    if (everyStep) {
      if (!observer(done ? tf : tcur, y)) {
        collectStats();
        fail(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(tcur));
        return res;
      }
    } else {
      while (next < ntspan && (tdir * (tcur - tspan[next]) >= 0.0 || (done && next + 1 == ntspan))) {
        const double tq = tspan[next++];
        const Eigen::VectorXd* out = &y;
        if (tq != tcur && !(done && next == ntspan)) {  // tf itself: the stop time, exactly
          if (CVodeGetDky(sd.mem, tq, 0, sd.dky) < 0) {
            collectStats();
            fail(OdeStatus::SolverFailure, "interpolation failed at t = " + text::shortest(tq));
            return res;
          }
          session.load(sd.dky, yout);
          out = &yout;
        }
        if (!observer(tq, *out)) {
          collectStats();
          fail(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(tcur));
          return res;
        }
      }
    }
    if (done) break;
    if (!hook(tcur, y)) {
      collectStats();
      return res;
    }
  }
  collectStats();
  res.tLast = tf;
  return res;
}

double Bdf::localTolerance(double relTol) {
  // CVODE's orders <= 2 end at about 6-10 RelTol on the guidance and the manipulator (RelTol 1e-4); a
  // third of it puts them at 2.5-5 (tools/bench/README.md, issue 48).
  return relTol / 3.0;
}

}  // namespace flexmb::solvers
