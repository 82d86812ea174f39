#include "tools/octave/MatlabUserFunctions.hpp"

#include "mex.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

namespace flexmb::octave_gateway {
namespace {

std::string timeText(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", t);
  return buf;
}

mxArray* column(const Eigen::VectorXd& v) {
  mxArray* a = mxCreateDoubleMatrix(v.size(), 1, mxREAL);
  if (v.size()) std::memcpy(mxGetPr(a), v.data(), v.size() * sizeof(double));
  return a;
}
mxArray* matrix(const Eigen::MatrixXd& m) {
  mxArray* a = mxCreateDoubleMatrix(m.rows(), m.cols(), mxREAL);
  if (m.size()) std::memcpy(mxGetPr(a), m.data(), m.size() * sizeof(double));
  return a;
}

// Calls fname(args...) with nout outputs through flexmb_usercall.m (which traps the function's
// error). Takes ownership of args; returns the outputs (caller destroys them). Throws
// core::UserFunctionError with `what` (e.g. "USERSIG function 'f' at t = 0.1") and the reason.
std::vector<mxArray*> call(const std::string& fname, int nout, std::vector<mxArray*> args, const std::string& what) {
  std::vector<mxArray*> in;
  in.push_back(mxCreateString(fname.c_str()));
  in.push_back(mxCreateDoubleScalar(nout));
  in.insert(in.end(), args.begin(), args.end());
  std::vector<mxArray*> out(2 + nout, nullptr);
  mxArray* trap =
      mexCallMATLABWithTrap(2 + nout, out.data(), static_cast<int>(in.size()), in.data(), "flexmb_usercall");
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
  Cached& c = cache_[order];
  if (!c.valid || c.t != t) {
    const std::string what =
        "USERINP function '" + inputFunction_ + "' at t = " + timeText(t) + " (is = " + std::to_string(order) + ")";
    std::vector<mxArray*> out = call(inputFunction_, 3, {mxCreateDoubleScalar(t), mxCreateDoubleScalar(order)}, what);
    Release release{out};
    const std::size_t nie = inputE_.size(), nix = inputX_.size();
    c.x = Eigen::VectorXd::Zero(model_.nx);
    c.e = Eigen::VectorXd::Zero(model_.ne);
    auto read = [&](const mxArray* a, const char* name, std::size_t nInputs, std::size_t nAll,
                    const std::vector<int>& inputs, const std::vector<int>& order, Eigen::VectorXd& dst) {
      if (nInputs == 0 && isEmpty(a)) return;
      const bool compact = vectorOf(a, nInputs), full = vectorOf(a, nAll);
      if (!compact && !full) {
        std::ostringstream m;
        m << what << " returned " << name << " of size " << (a ? mxGetM(a) : 0) << " x " << (a ? mxGetN(a) : 0)
          << "; expected " << nInputs << " values (the inputs) or " << nAll << " (all, SPACAR order)";
        throw core::UserFunctionError(m.str());
      }
      const double* p = mxGetPr(a);
      if (compact) {
        for (std::size_t k = 0; k < nInputs; ++k) dst[inputs[k]] = p[k];
      } else {
        for (std::size_t k = 0; k < nAll; ++k) dst[order[k]] = p[k];
      }
      if (!dst.allFinite()) throw core::UserFunctionError(what + " returned a non-finite value in " + name);
    };
    read(out[1], "e", nie, model_.ne, inputE_, layout_.eOrder, c.e);
    read(out[2], "x", nix, model_.nx, inputX_, layout_.xOrder, c.x);
    c.valid = true;
    c.t = t;
  }
  return deformation ? c.e[index] : c.x[index];
}

void MatlabUserFunctions::loads(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::VectorXd& e,
                                const Eigen::VectorXd& ed, Eigen::VectorXd& sigma, Eigen::VectorXd& f) {
  const std::string what = "USERSIG function '" + stressFunction_ + "' at t = " + timeText(t);
  const Eigen::VectorXd zx = Eigen::VectorXd::Zero(model_.nx), ze = Eigen::VectorXd::Zero(model_.ne);
  std::vector<mxArray*> out =
      call(stressFunction_, 3,
           {mxCreateDoubleScalar(t), mxCreateDoubleScalar(model_.ne), matrix(topology_.le), column(layout_.sortE(e)),
            column(ed.size() ? layout_.sortE(ed) : ze), mxCreateDoubleScalar(model_.nx), matrix(topology_.lnp),
            column(layout_.sortX(x)), column(xd.size() ? layout_.sortX(xd) : zx)},
           what);
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

}  // namespace flexmb::octave_gateway
