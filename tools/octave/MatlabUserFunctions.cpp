#include "tools/octave/MatlabUserFunctions.hpp"

#include "mex.h"

#include "text/NumberText.hpp"
#include "tools/octave/OctaveInterrupt.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

namespace flexmb::octave_gateway {
namespace {

std::string timeText(double t) { return text::significant(t, 10); }

// A 1 x n row: SPACAR passes vectors to user functions as rows (FIS's FFESFVA indexes
// x(lnp(n, :)) and multiplies 2*Q_bar'*qp', which needs 1 x 4 rows).
mxArray* row(const Eigen::VectorXd& v) {
  mxArray* a = mxCreateDoubleMatrix(1, v.size(), mxREAL);
  if (v.size()) std::memcpy(mxGetPr(a), v.data(), v.size() * sizeof(double));
  return a;
}
mxArray* matrix(const Eigen::MatrixXd& m) {
  mxArray* a = mxCreateDoubleMatrix(m.rows(), m.cols(), mxREAL);
  if (m.size()) std::memcpy(mxGetPr(a), m.data(), m.size() * sizeof(double));
  return a;
}

// Calls fname(args...) with nout outputs through flexmb_usercall.m (which traps the function's
// error). Takes ownership of args; returns the outputs (caller destroys them); adds the call and its
// wall time to `stats`. Throws core::UserFunctionError with `what` (e.g. "USERSIG function 'f' at
// t = 0.1") and the reason.
std::vector<mxArray*> call(const std::string& fname, int nout, std::vector<mxArray*> args, const std::string& what,
                           MatlabUserFunctions::CallStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  struct Clock {  // counts the call however it ends
    MatlabUserFunctions::CallStats& s;
    std::chrono::steady_clock::time_point t0;
    ~Clock() {
      ++s.calls;
      s.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  } clock{stats, start};
  std::vector<mxArray*> in;
  in.push_back(mxCreateString(fname.c_str()));
  in.push_back(mxCreateDoubleScalar(nout));
  in.insert(in.end(), args.begin(), args.end());
  std::vector<mxArray*> out(2 + nout, nullptr);
  mxArray* trap = nullptr;
  try {
    trap = mexCallMATLABWithTrap(2 + nout, out.data(), static_cast<int>(in.size()), in.data(), "flexmb_usercall");
  } catch (...) {
    // Not an error of the function (flexmb_usercall traps those): Ctrl-C in the interpreter, which
    // unwinds through here. It must not unwind through the integrator: the run stops as interrupted.
    for (mxArray* a : in) mxDestroyArray(a);
    if (isInterpreterInterrupt(std::current_exception())) {
      noteInterpreterInterrupt();
      throw core::UserFunctionError(what + ": interrupted (Ctrl-C)");
    }
    throw core::UserFunctionError(what + ": the interpreter raised an exception that is not an error");
  }
  for (mxArray* a : in) mxDestroyArray(a);
  if (trap) {
    mxDestroyArray(trap);
    throw core::UserFunctionError(
        what + ": flexmb_usercall.m (shipped beside spacar) could not be called; is its folder on the path?");
  }
  const bool ok = out[0] && mxGetScalar(out[0]) != 0.0;
  std::string msg;
  if (!ok && out[1] && mxIsChar(out[1])) {
    char* s = mxArrayToString(out[1]);
    msg = s ? s : "";
    mxFree(s);
  }
  mxDestroyArray(out[0]);
  mxDestroyArray(out[1]);
  std::vector<mxArray*> results(out.begin() + 2, out.end());
  if (!ok) {
    for (mxArray* a : results)
      if (a) mxDestroyArray(a);
    throw core::UserFunctionError(what + " failed: " + msg);
  }
  return results;
}

struct Release {
  std::vector<mxArray*>& v;
  ~Release() {
    for (mxArray* a : v)
      if (a) mxDestroyArray(a);
  }
};

// A real numeric vector of n values (row or column), or empty when allowEmpty.
bool vectorOf(const mxArray* a, std::size_t n) {
  return a && mxIsDouble(a) && !mxIsComplex(a) && mxGetNumberOfElements(a) == n && (mxGetM(a) == 1 || mxGetN(a) == 1);
}
bool isEmpty(const mxArray* a) { return !a || mxIsEmpty(a); }

// One USERINP channel: value, rate or acceleration of one input.
class InputChannel : public core::TimeFunction {
 public:
  InputChannel(MatlabUserFunctions* owner, std::string name, int order, bool deformation, int index)
      : owner_(owner), name_(std::move(name)), order_(order), deformation_(deformation), index_(index) {}
  double value(double t) const override { return owner_->input(t, order_, deformation_, index_); }
  std::string text() const override { return name_ + "(t, " + std::to_string(order_) + ")"; }

 private:
  MatlabUserFunctions* owner_;
  std::string name_;
  int order_;
  bool deformation_;
  int index_;
};

}  // namespace

MatlabUserFunctions::MatlabUserFunctions(core::Model& model)
    : model_(model),
      stressFunction_(model.userStressFunction),
      inputFunction_(model.userInputFunction),
      layout_(io::spacarLayout(model)),
      topology_(io::spacarTopology(model, layout_)) {
  for (int i = layout_.nxp[0] + layout_.nxp[1]; i < layout_.nxp[0] + layout_.nxp[1] + layout_.nxp[2]; ++i)
    inputX_.push_back(layout_.xOrder[i]);
  for (int j = layout_.nep[0]; j < layout_.nep[0] + layout_.nep[2]; ++j) inputE_.push_back(layout_.eOrder[j]);
  if (inputFunction_.empty()) return;
  // Channels are owned by the model's inputs; they point back here (the model outlives nothing of
  // this object's use: both live for one spacar() call).
  auto install = [&](core::Rheonomic& r, bool deformation) {
    r.fx = std::make_shared<InputChannel>(this, inputFunction_, 0, deformation, r.index);
    r.fv = std::make_shared<InputChannel>(this, inputFunction_, 1, deformation, r.index);
    r.fa = std::make_shared<InputChannel>(this, inputFunction_, 2, deformation, r.index);
  };
  for (auto& r : model.inputX) install(r, false);
  for (auto& r : model.inputE) install(r, true);
}

double MatlabUserFunctions::input(double t, int order, bool deformation, int index) {
  if (!cache_.valid || cache_.t != t) {
    // One call gives value, rate and acceleration of every input (SPACAR's convention; `is` is
    // passed as 0 and FIS's USERINP ignores it).
    const std::string what = "USERINP function '" + inputFunction_ + "' at t = " + timeText(t);
    std::vector<mxArray*> out =
        call(inputFunction_, 3, {mxCreateDoubleScalar(t), mxCreateDoubleScalar(0.0)}, what, inputStats_);
    Release release{out};
    readInputRows(out[1], true, what, cache_.e);
    readInputRows(out[2], false, what, cache_.x);
    cache_.valid = true;
    cache_.t = t;
  }
  return (deformation ? cache_.e : cache_.x)(index, order);
}

void MatlabUserFunctions::readInputRows(const mxArray* a, bool deformation, const std::string& what,
                                        Eigen::MatrixXd& dst) const {
  const char* name = deformation ? "e" : "x";
  const std::vector<int>& inputs = deformation ? inputE_ : inputX_;
  const int n = deformation ? model_.ne : model_.nx;
  dst.setConstant(n, 3, std::numeric_limits<double>::quiet_NaN());
  const std::string form =
      deformation ? "[element deformation value rate acceleration]" : "[node component value rate acceleration]";
  if (isEmpty(a)) {
    if (inputs.empty()) return;
  } else if (!mxIsDouble(a) || mxIsComplex(a) || mxGetN(a) != 5) {
    throw core::UserFunctionError(what + " returned " + name + " of size " + std::to_string(mxGetM(a)) + " x " +
                                  std::to_string(mxGetN(a)) + "; expected one row " + form + " per input " +
                                  (deformation ? "deformation" : "coordinate") + " (" + std::to_string(inputs.size()) +
                                  (inputs.empty() ? ", so [])" : ")"));
  }
  const std::size_t rows = isEmpty(a) ? 0 : mxGetM(a);
  const double* p = rows ? mxGetPr(a) : nullptr;
  for (std::size_t r = 0; r < rows; ++r) {
    const double label = p[r], comp = p[rows + r];
    const std::string row = what + ": " + name + " row " + std::to_string(r + 1) + " ";
    int index = -1;
    if (deformation) {
      const auto it = model_.elementByLabel.find(static_cast<int>(label));
      if (label != std::floor(label) || it == model_.elementByLabel.end())
        throw core::UserFunctionError(row + "names element " + timeText(label) + ", which the model does not have");
      const core::ElementEntry& el = model_.elements[it->second];
      const int nd = el.impl ? el.impl->numDeformations() : 0;
      if (comp != std::floor(comp) || comp < 1 || comp > nd)
        throw core::UserFunctionError(row + "names deformation " + timeText(comp) + " of element " +
                                      std::to_string(el.label) + ", which has " + std::to_string(nd));
      index = el.firstDef + static_cast<int>(comp) - 1;
      if (model_.eRole[index] != core::Role::Input)
        throw core::UserFunctionError(row + "names " + model_.deformationName(index) +
                                      ", which is not an input deformation (INPUTE)");
    } else {
      const auto it = model_.nodeByLabel.find(static_cast<int>(label));
      if (label != std::floor(label) || it == model_.nodeByLabel.end())
        throw core::UserFunctionError(row + "names node " + timeText(label) + ", which the model does not have");
      const core::Node& nd = model_.nodes[it->second];
      if (comp != std::floor(comp) || comp < 1 || comp > nd.dim())
        throw core::UserFunctionError(row + "names component " + timeText(comp) + " of node " +
                                      std::to_string(nd.label) + ", which has " + std::to_string(nd.dim()));
      index = nd.firstCoord + static_cast<int>(comp) - 1;
      if (model_.xRole[index] != core::Role::Input)
        throw core::UserFunctionError(row + "names " + model_.coordName(index) +
                                      ", which is not an input coordinate (INPUTX)");
    }
    if (!std::isnan(dst(index, 0)))
      throw core::UserFunctionError(
          row + "names " + (deformation ? model_.deformationName(index) : model_.coordName(index)) + " a second time");
    for (int k = 0; k < 3; ++k) {
      dst(index, k) = p[(2 + k) * rows + r];
      if (!std::isfinite(dst(index, k))) throw core::UserFunctionError(row + "holds a non-finite value");
    }
  }
  for (int i : inputs)
    if (std::isnan(dst(i, 0)))
      throw core::UserFunctionError(what + " returned no row of " + name + " for the input " +
                                    (deformation ? model_.deformationName(i) : model_.coordName(i)) + " (rows " + form +
                                    ")");
}

void MatlabUserFunctions::loads(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::VectorXd& e,
                                const Eigen::VectorXd& ed, Eigen::VectorXd& sigma, Eigen::VectorXd& f) {
  const std::string what = "USERSIG function '" + stressFunction_ + "' at t = " + timeText(t);
  const Eigen::VectorXd zx = Eigen::VectorXd::Zero(model_.nx), ze = Eigen::VectorXd::Zero(model_.ne);
  std::vector<mxArray*> out =
      call(stressFunction_, 3,
           {mxCreateDoubleScalar(t), mxCreateDoubleScalar(model_.ne), matrix(topology_.le), row(layout_.sortE(e)),
            row(ed.size() ? layout_.sortE(ed) : ze), mxCreateDoubleScalar(model_.nx), matrix(topology_.lnp),
            row(layout_.sortX(x)), row(xd.size() ? layout_.sortX(xd) : zx)},
           what, stressStats_);
  Release release{out};
  sigma = Eigen::VectorXd::Zero(model_.ne);
  f = Eigen::VectorXd::Zero(model_.nx);
  const mxArray* s = out[1];
  if (!isEmpty(s)) {
    if (!vectorOf(s, model_.ne))
      throw core::UserFunctionError(what + " returned sig of size " + std::to_string(mxGetM(s)) + " x " +
                                    std::to_string(mxGetN(s)) + "; expected ne = " + std::to_string(model_.ne) +
                                    " values (SPACAR order, see le) or []");
    const double* p = mxGetPr(s);
    for (int k = 0; k < model_.ne; ++k) sigma[layout_.eOrder[k]] = p[k];
  }
  const mxArray* F = out[2];
  if (!isEmpty(F)) {
    if (!mxIsDouble(F) || mxIsComplex(F) || mxGetN(F) != 3)
      throw core::UserFunctionError(what + " returned f of size " + std::to_string(mxGetM(F)) + " x " +
                                    std::to_string(mxGetN(F)) + "; expected rows [node component value]");
    const double* p = mxGetPr(F);
    const std::size_t rows = mxGetM(F);
    for (std::size_t r = 0; r < rows; ++r) {
      const double node = p[r], comp = p[rows + r], value = p[2 * rows + r];
      const auto it = model_.nodeByLabel.find(static_cast<int>(node));
      if (node != std::floor(node) || it == model_.nodeByLabel.end())
        throw core::UserFunctionError(what + ": f row " + std::to_string(r + 1) + " names node " + timeText(node) +
                                      ", which the model does not have");
      const core::Node& n = model_.nodes[it->second];
      if (comp != std::floor(comp) || comp < 1 || comp > n.dim())
        throw core::UserFunctionError(what + ": f row " + std::to_string(r + 1) + ": node " + std::to_string(n.label) +
                                      " has no component " + timeText(comp));
      f[n.firstCoord + static_cast<int>(comp) - 1] += value;
    }
  }
  if (!sigma.allFinite() || !f.allFinite()) throw core::UserFunctionError(what + " returned a non-finite value");
}

std::string MatlabUserFunctions::timing() const {
  std::ostringstream s;
  auto one = [&](const char* key, const std::string& name, const CallStats& c) {
    if (name.empty()) return;
    s << (s.tellp() > 0 ? "; " : "") << key << " " << name << ": " << c.calls << " calls, " << c.seconds << " s";
    if (c.calls) s << " (" << 1e3 * c.seconds / static_cast<double>(c.calls) << " ms per call)";
  };
  one("USERSIG", stressFunction_, stressStats_);
  one("USERINP", inputFunction_, inputStats_);
  return s.str();
}

}  // namespace flexmb::octave_gateway
