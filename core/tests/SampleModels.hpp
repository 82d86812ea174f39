#pragma once
// Sample models for the core tests, built in code with core::ModelBuilder only (no file reading, no
// io): the statements of a .dat file, in the file's order (node and dof numbering follow it), with
// the file's numbers. io/tests/test_sample_models.cpp reads each mirrored file and checks that the
// two give the same model (topology, roles, x0, parameters, loads, settings and a kinematic solve),
// so a copy cannot drift from its file.
#include <cmath>
#include <functional>
#include <initializer_list>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "core/model/Model.hpp"
#include "core/model/ModelBuilder.hpp"

namespace flexmb::core::samples {

// A function of time given in C++ (the stand-in of a .dat expression; text is the expression).
class FunctionOfTime final : public TimeFunction {
 public:
  FunctionOfTime(std::function<double(double)> f, std::string text) : f_(std::move(f)), text_(std::move(text)) {}
  double value(double t) const override { return f_(t); }
  std::string text() const override { return text_; }

 private:
  std::function<double(double)> f_;
  std::string text_;
};
inline TimeFunctionPtr function(std::function<double(double)> f, std::string text) {
  return std::make_shared<FunctionOfTime>(std::move(f), std::move(text));
}

// The .dat statements as ModelBuilder calls (the calls io::DatReader makes for each keyword), each
// with its own line number for messages.
class SampleBuilder {
 public:
  explicit SampleBuilder(const std::string& name, Dialect dialect = Dialect::Spacar2013) : b_(name), d_(dialect) {
    b_.setDialect(dialect);
  }
  SampleBuilder& element(const char* keyword, int label, std::initializer_list<int> nodes,
                         std::initializer_list<double> vector = {}) {
    const ElementTypeInfo* t = findElementType(keyword);
    if (!t) throw std::invalid_argument(std::string("no element type ") + keyword);
    const std::vector<int> n(nodes);
    const std::vector<double> v(vector);
    if (t->vector.empty())
      b_.addElement(*t, label, n, ++line_);
    else
      b_.addElement(*t, label, n, v, ++line_);
    return *this;
  }
  SampleBuilder& x(int node, std::initializer_list<double> values) {  // X, XY, BETA
    b_.setCoordinates(node, std::vector<double>(values), ++line_);
    return *this;
  }
  SampleBuilder& fix(int node, std::initializer_list<int> comps = {}) { return xRole(node, comps, Role::Fixed); }
  SampleBuilder& inputx(int node, std::initializer_list<int> comps = {}) { return xRole(node, comps, Role::Input); }
  SampleBuilder& dynx(int node, std::initializer_list<int> comps = {}) { return xRole(node, comps, Role::Dynamic); }
  SampleBuilder& dyne(int el, std::initializer_list<int> comps = {}) { return eRole(el, comps, Role::Dynamic); }
  SampleBuilder& rlse(int el, std::initializer_list<int> comps = {}) { return eRole(el, comps, Role::Calculable); }
  SampleBuilder& inpute(int el, std::initializer_list<int> comps = {}) { return eRole(el, comps, Role::Input); }
  SampleBuilder& em(int el, std::initializer_list<double> values) {  // EM, EMASS
    b_.setElementInertia(el, std::vector<double>(values), ++line_);
    return *this;
  }
  SampleBuilder& xm(int node, double value) {  // XM n m, MASS
    b_.setLumpedMass(node, value, ++line_);
    return *this;
  }
  SampleBuilder& estiff(int el, std::initializer_list<double> values) {
    b_.setStiffness(el, std::vector<double>(values), ++line_);
    return *this;
  }
  SampleBuilder& edamp(int el, std::initializer_list<double> values) {
    b_.setDamping(el, std::vector<double>(values), ++line_);
    return *this;
  }
  SampleBuilder& xf(int node, std::initializer_list<double> values) {
    b_.addForce(node, std::vector<double>(values), ++line_);
    return *this;
  }
  SampleBuilder& delxf(int node, std::initializer_list<double> values) {
    b_.addForceIncrement(node, std::vector<double>(values), ++line_);
    return *this;
  }
  SampleBuilder& xft(int node, int comp, TimeFunctionPtr f) {
    b_.addTimeForce(node, comp, std::move(f), ++line_);
    return *this;
  }
  SampleBuilder& eref(int el, int comp, TimeFunctionPtr f) {
    b_.setReference(el, comp, std::move(f), ++line_);
    return *this;
  }
  SampleBuilder& inputet(int el, int comp, TimeFunctionPtr e, TimeFunctionPtr v, TimeFunctionPtr a) {
    b_.setInputDeformationFunctions(el, comp, std::move(e), std::move(v), std::move(a), ++line_);
    return *this;
  }
  // E, ED, STARTDE
  SampleBuilder& initialDeformation(int el, int comp, std::optional<double> e, std::optional<double> ed) {
    b_.setInitialDeformation(el, comp, e, ed, std::nullopt, ++line_);
    return *this;
  }
  SampleBuilder& gravity(double gx, double gy, double gz = 0.0) {
    b_.setGravity(gx, gy, gz, ++line_);
    return *this;
  }
  // TIMESTEP: SPACAR 2013+ `TIMESTEP T n`, SPACAR95 `TIMESTEP n T` (a period from the start).
  SampleBuilder& timestep(double tEnd, int intervals) {
    AnalysisSettings& s = b_.settings();
    s.tEnd = d_ == Dialect::Spacar95 ? s.t0 + tEnd : tEnd;
    s.outputIntervals = intervals;
    s.timestepGiven = true;
    return *this;
  }
  // ITERSTEP maxit steps [tol]
  SampleBuilder& iterstep(int maxIterations, int loadSteps, std::optional<double> tol = std::nullopt) {
    AnalysisSettings& s = b_.settings();
    s.maxIterations = maxIterations;
    s.loadSteps = loadSteps;
    if (tol) s.kinematicTol = *tol, s.kinematicTolGiven = true;
    return *this;
  }
  AnalysisSettings& settings() { return b_.settings(); }
  // The model, with the dialect's PLBEAM elongation; without TIMESTEP the default period, as the reader.
  Model finalize() {
    AnalysisSettings& s = b_.settings();
    if (!s.timestepGiven) s.tEnd = std::max(s.tEnd, s.t0 + 1.0);
    ElementOptions o;
    o.elongation = d_ == Dialect::Spacar95 ? ElongationDefinition::Plain : ElongationDefinition::BendingCorrected;
    return b_.finalize(o);
  }

 private:
  SampleBuilder& xRole(int node, std::initializer_list<int> comps, Role r) {
    b_.setCoordinateRole(node, std::vector<int>(comps), r, ++line_);
    return *this;
  }
  SampleBuilder& eRole(int el, std::initializer_list<int> comps, Role r) {
    b_.setDeformationRole(el, std::vector<int>(comps), r, ++line_);
    return *this;
  }
  ModelBuilder b_;
  Dialect d_;
  int line_ = 0;
};

// datfiles/straight_guidance.dat: the paper's straight guidance (Fig. 2), two leaf springs of five
// PLBEAMs each and a rigid intermediate body; 17 DOF (bending DYNE, released end hinges), the pulse
// XFT on node 6.
inline Model straightGuidance() {
  SampleBuilder s("straight_guidance.dat");
  for (int k = 1; k <= 5; ++k) s.element("PLBEAM", k, {k, 100 + k, k + 1, 101 + k});
  for (int k = 11; k <= 15; ++k) s.element("PLBEAM", k, {k, 100 + k, k + 1, 101 + k});
  s.element("PLBEAM", 21, {6, 106, 16, 116});
  const double y[6] = {0.0, 0.04, 0.08, 0.12, 0.16, 0.2};
  for (int k = 0; k < 6; ++k) s.x(1 + k, {0.0, y[k]});
  for (int k = 0; k < 6; ++k) s.x(11 + k, {0.2, y[k]});
  s.fix(1).fix(101).fix(11).fix(111);
  for (int k = 1; k <= 4; ++k) s.dyne(k, {2, 3});
  s.dyne(5, {2});
  for (int k = 11; k <= 14; ++k) s.dyne(k, {2, 3});
  s.rlse(5, {3}).rlse(15, {2, 3});
  for (int k : {1, 2, 3, 4, 5, 11, 12, 13, 14, 15}) s.em(k, {0.228, 1.9e-8});
  s.em(21, {6.84, 5.13e-4});
  for (int k : {1, 2, 3, 4, 5, 11, 12, 13, 14, 15}) s.estiff(k, {6.3e6, 0.525});
  s.xft(6, 1,
        function([](double t) { return t <= 0.1 ? 50 * (1 - std::cos(20 * std::numbers::pi * t)) : 0.0; },
                 "t <= 0.1 ? 50*(1-cos(20*_pi*t)) : 0"));
  s.timestep(0.2, 200);
  s.settings().absTol = 1e-6, s.settings().relTol = 1e-3;  // ERROR 1e-6 1e-3
  return s.finalize();
}

// The four-bar of datfiles/tests/ (A, B, C, D; crank 0.1, coupler 0.3, rocker 0.25, ground 0.3),
// rigid PLBEAMs and PLHINGEs, q the crank angle (DYNE 4 1). Variants: fourbar.dat (released
// hinges 5, 6, 7: 1 DOF), underconstrained.dat (hinge 6 left out, the rocker's bending at C released:
// node 32 is undetermined), overconstrained.dat (hinge 6 present but fixed: a self-stressed loop).
enum class FourBar { Mobile, Underconstrained, Overconstrained };
inline Model fourBar(FourBar variant = FourBar::Mobile) {
  const char* names[] = {"fourbar.dat", "underconstrained.dat", "overconstrained.dat"};
  SampleBuilder s(names[static_cast<int>(variant)]);
  s.element("PLBEAM", 1, {1, 11, 2, 12}).element("PLBEAM", 2, {2, 21, 3, 22}).element("PLBEAM", 3, {4, 31, 3, 32});
  s.element("PLHINGE", 4, {10, 11}).element("PLHINGE", 5, {12, 21});
  if (variant != FourBar::Underconstrained) s.element("PLHINGE", 6, {22, 32});
  s.element("PLHINGE", 7, {10, 31});
  s.x(1, {0.0, 0.0}).x(2, {0.0, 0.1}).x(3, {0.261506227481982, 0.24701868244594594}).x(4, {0.3, 0.0});
  s.x(10, {0.0}).x(11, {1.5707963267948966}).x(12, {1.5707963267948966});
  s.x(21, {0.51216119318615}).x(22, {0.51216119318615});
  s.x(31, {1.7253864163355364}).x(32, {1.7253864163355364});
  s.fix(1).fix(4).fix(10);
  s.dyne(4, {1}).rlse(5, {1});
  if (variant == FourBar::Mobile) s.rlse(6, {1});
  s.rlse(7, {1});
  if (variant == FourBar::Underconstrained) s.rlse(3, {3});
  for (int k = 1; k <= 3; ++k) s.em(k, {1.0, 1e-6});
  if (variant == FourBar::Mobile) s.initialDeformation(4, 1, 0.0, 6.283185307179586);
  s.timestep(2.0, 200);
  return s.finalize();
}

// core/tests/ModelTexts.hpp swungArm() with its default arguments: a flexible arm of three
// PLBEAMs swung by a prescribed hinge angle 0.3 + 2 t + 0.75 t^2 (INPUTET), with distributed and
// lumped mass, damping, a tip load and gravity: every optional term of Eq. 13.
inline Model swungArm() {
  SampleBuilder s("swung_arm.dat");
  s.element("PLHINGE", 10, {100, 101});
  for (int k = 1; k <= 3; ++k) s.element("PLBEAM", k, {k, 100 + k, k + 1, 101 + k});
  s.x(1, {0.0, 0.0}).x(2, {0.4, 0.0}).x(3, {0.8, 0.0}).x(4, {1.2, 0.0});  // the text's 6 digits of 0.4 (k - 1)
  s.fix(1).fix(100).inpute(10, {1});
  for (int k = 1; k <= 3; ++k) s.dyne(k, {1, 2, 3});
  s.inputet(10, 1, function([](double t) { return 0.3 + 2 * t + 0.75 * std::pow(t, 2); }, "0.3 + 2*t + 0.75*t^2"),
            function([](double t) { return 2 + 1.5 * t; }, "2 + 1.5*t"), function([](double) { return 1.5; }, "1.5"));
  for (int k = 1; k <= 3; ++k) s.em(k, {1.7, 2e-4}).estiff(k, {4e4, 30}).edamp(k, {2, 0.05});
  s.xm(4, 0.3).xf(4, {0.5, -2}).gravity(0, -9.81);
  return s.finalize();
}

// datfiles/cantilever.dat: four PLBEAMs of 0.25 m clamped at node 1, every deformation DYNE, tip
// load increment DELXF 5 0 -0.1.
inline Model cantilever() {
  SampleBuilder s("cantilever.dat");
  for (int k = 1; k <= 4; ++k) s.element("PLBEAM", k, {k, 100 + k, k + 1, 101 + k});
  s.x(1, {0.0, 0.0}).x(2, {0.25, 0.0}).x(3, {0.5, 0.0}).x(4, {0.75, 0.0}).x(5, {1.0, 0.0});
  s.fix(1).fix(101);
  for (int k = 1; k <= 4; ++k) s.dyne(k, {1, 2, 3});
  for (int k = 1; k <= 4; ++k) s.em(k, {0.312, 1.04e-7});
  for (int k = 1; k <= 4; ++k) s.estiff(k, {8.4e6, 2.8});
  s.delxf(5, {0.0, -0.1});
  s.iterstep(10, 1).timestep(1.0, 100);
  return s.finalize();
}

// datfiles/portal.dat: two legs of two PLBEAMs and a rigid top beam, a closed frame; DELXF 3 5 0.
inline Model portal() {
  SampleBuilder s("portal.dat");
  s.element("PLBEAM", 1, {1, 101, 2, 102}).element("PLBEAM", 2, {2, 102, 3, 103});
  s.element("PLBEAM", 11, {11, 111, 12, 112}).element("PLBEAM", 12, {12, 112, 13, 113});
  s.element("PLBEAM", 21, {3, 103, 13, 113});
  s.x(1, {0.0, 0.0}).x(2, {0.0, 0.1}).x(3, {0.0, 0.2}).x(11, {0.2, 0.0}).x(12, {0.2, 0.1}).x(13, {0.2, 0.2});
  s.fix(1).fix(101).fix(11).fix(111);
  s.dyne(1, {2, 3}).dyne(2, {2}).dyne(11, {2, 3}).rlse(2, {3}).rlse(12, {2, 3});
  for (int k : {1, 2, 11, 12}) s.em(k, {0.228, 1.9e-8});
  s.em(21, {6.84, 5.13e-4});
  for (int k : {1, 2, 11, 12}) s.estiff(k, {6.3e6, 0.525});
  s.delxf(3, {5.0, 0.0});
  s.iterstep(10, 1).timestep(0.1, 100);
  return s.finalize();
}

// The reference angle of the manipulator's hinges (datfiles/manipulator.dat EREF): a rest-to-rest
// turn from -pi/4 ... to pi/2 in 0.5 s, the hinge 2 its mirror image.
// Written as the file's expression evaluates it (t^n is pow).
inline double manipulatorReference(double t) {
  const double a = std::numbers::pi / 4;
  if (t < 1.0 / 6) return a * (-1 + 72 * std::pow(t, 3)) + a;
  if (t < 1.0 / 3) return a * (-18 * t + 108 * std::pow(t, 2) - 144 * std::pow(t, 3)) + a;
  if (t < 1.0 / 2) return a * (-8 + 54 * t - 108 * std::pow(t, 2) + 72 * std::pow(t, 3)) + a;
  return std::numbers::pi / 2;
}

// datfiles/manipulator.dat: the paper's two-link flexible manipulator (Fig. 6), an open chain of
// two PLHINGEs (servo springs toward the reference angles EREF) and 2 x 4 PLBEAMs; 18 DOF.
inline Model manipulator() {
  SampleBuilder s("manipulator.dat");
  s.element("PLHINGE", 1, {100, 101}).element("PLHINGE", 2, {105, 201});
  for (int k = 1; k <= 4; ++k) s.element("PLBEAM", 10 + k, {k, 100 + k, k + 1, 101 + k});
  for (int k = 1; k <= 4; ++k) s.element("PLBEAM", 20 + k, {4 + k, 200 + k, 5 + k, 201 + k});
  s.x(1, {0.0, 0.0}).x(2, {0.096343298936667100, -0.096343298936667100});
  s.x(3, {0.19268659787333420, -0.19268659787333420}).x(4, {0.28902989681000130, -0.28902989681000130});
  s.x(5, {0.38537319574666840, -0.38537319574666840});
  s.x(6, {0.55412319574666840, -0.38537319574666840}).x(7, {0.72287319574666840, -0.38537319574666840});
  s.x(8, {0.89162319574666840, -0.38537319574666840}).x(9, {1.0603731957466684, -0.38537319574666840});
  s.x(100, {0.0});
  for (int k = 101; k <= 105; ++k) s.x(k, {-0.78539816339744831});
  for (int k = 201; k <= 205; ++k) s.x(k, {0.0});
  s.fix(1).fix(100).dyne(1, {1}).dyne(2, {1});
  for (int k : {11, 12, 13, 14, 21, 22, 23, 24}) s.dyne(k, {2, 3});
  s.xm(5, 1.0).xm(9, 3.0);
  for (int k = 11; k <= 14; ++k) s.em(k, {2.43, 4.563e-5});
  for (int k = 21; k <= 24; ++k) s.em(k, {1.08, 8.991e-6});
  for (int k = 11; k <= 14; ++k) s.estiff(k, {6.57e7, 1233.7});
  for (int k = 21; k <= 24; ++k) s.estiff(k, {2.92e7, 243.09});
  s.estiff(1, {5e3}).estiff(2, {5e3});
  s.eref(1, 1, function(manipulatorReference, "the rest-to-rest turn of manipulator.dat"));
  s.eref(2, 1, function([](double t) { return -manipulatorReference(t); }, "its mirror image"));
  s.timestep(0.7, 700);
  s.settings().absTol = 1e-6, s.settings().relTol = 1e-3;  // ERROR 1e-6 1e-3
  return s.finalize();
}

// datfiles/slider_crank_s95.dat (SPACAR95): a rigid crank, a flexible rod (every deformation DYNE)
// and a slider on the x axis; 4 DOF, no damping, gravity or loads, so the energy is conserved.
inline Model sliderCrankS95() {
  SampleBuilder s("slider_crank_s95.dat", Dialect::Spacar95);
  s.element("PLBEAM", 1, {1, 12, 2, 13}).element("PLBEAM", 2, {2, 14, 3, 15}).element("PLHINGE", 3, {11, 12});
  s.x(1, {0.0, 0.0}).x(2, {0.15, 0.0}).x(3, {0.45, 0.0});
  for (int k = 11; k <= 15; ++k) s.x(k, {0.0});
  s.fix(1).fix(11).fix(3, {2});
  s.dyne(3, {1}).dyne(2, {1, 2, 3});
  s.em(1, {1.0}).em(2, {0.5}).xm(3, 0.2).estiff(2, {8000.0, 0.4});
  s.initialDeformation(3, 1, std::nullopt, 6.283185307179586);  // ED 3 1
  s.timestep(5.0, 500);
  s.settings().relTol = s.settings().absTol = 1.0E-6;  // EPSINT
  return s.finalize();
}

// datfiles/spatial/cross_spring_pivot_coarse.dat: a spatial cross-spring pivot, two leaf springs of
// three BEAMs each (one with released deformations) and a platform BEAM, under gravity, a force and
// a moment increment on the platform (DELXF on an orientation node: a global moment).
inline Model crossSpringPivot() {
  SampleBuilder s("cross_spring_pivot_coarse.dat");
  s.x(1, {0.000000, 0.000000, 0.000000}).x(3, {0.100000, 0.100000, 0.000000});
  s.x(5, {0.000000, 0.100000, 0.000000}).x(7, {0.100000, 0.000000, 0.000000});
  s.x(9, {0.033333, 0.033333, 0.000000}).x(11, {0.066667, 0.066667, 0.000000});
  s.x(13, {0.033333, 0.066667, 0.000000}).x(15, {0.066667, 0.033333, 0.000000});
  const std::initializer_list<double> z = {0.000000, 0.000000, 1.000000};
  s.element("BEAM", 1, {1, 2, 9, 10}, z).element("BEAM", 2, {9, 10, 11, 12}, z).element("BEAM", 3, {11, 12, 3, 4}, z);
  s.element("BEAM", 4, {5, 6, 13, 14}, z).element("BEAM", 5, {13, 14, 15, 16}, z).element("BEAM", 6, {15, 16, 7, 8}, z);
  s.element("BEAM", 7, {3, 4, 7, 8}, z);
  for (int k = 1; k <= 5; ++k) s.dyne(k, {1, 2, 3, 4, 5, 6});
  s.rlse(6, {1, 2, 3, 4, 5, 6});
  s.fix(1).fix(2).fix(5).fix(6);
  for (int k = 1; k <= 6; ++k)
    s.estiff(k, {2100000.000000000000000, 0.009309804722106, 0.007000000000000, 437.500000000000114, 0.000000011666667,
                 0.000729166666667});
  for (int k = 1; k <= 7; ++k)
    s.em(k, {0.078000000000000, 0.000016250260000, 0.000000000260000, 0.000016250000000, 0.000000000000000});
  s.gravity(0.000000, 0.000000, -9.810000);
  s.iterstep(10, 9, 5e-7);
  s.delxf(3, {0.000000, -0.020000, 0.000000}).delxf(4, {0.000000, 0.000000, 0.005000});
  return s.finalize();
}

// A sloped cantilever of four PLBEAMs with distributed mass under gravity (no tip load): the
// gravity load stiffness of LinearizationInMotion.StaticTangentIncludesGravityLoadStiffness.
inline Model gravityCantilever() {
  SampleBuilder s("gravity_cantilever.dat");
  for (int k = 1; k <= 4; ++k) s.element("PLBEAM", k, {k, 100 + k, k + 1, 101 + k});
  // The text prints 0.3 (k - 1) and 0.1 (k - 1) with 6 digits: 0.9 and 0.3, not 3 x 0.3 and 3 x 0.1.
  s.x(1, {0.0, 0.0}).x(2, {0.3, 0.1}).x(3, {0.6, 0.2}).x(4, {0.9, 0.3}).x(5, {1.2, 0.4});
  s.fix(1).fix(101);
  for (int k = 1; k <= 4; ++k) s.dyne(k, {1, 2, 3});
  for (int k = 1; k <= 4; ++k) s.em(k, {2.5, 3e-3}).estiff(k, {1e3, 4});
  s.gravity(0.5, -9.81);
  return s.finalize();
}

// Every sample with its name (the registry-style loops of the core tests).
struct NamedSample {
  std::string name;
  std::function<Model()> build;
};
inline std::vector<NamedSample> allSamples() {
  return {{"straight guidance", straightGuidance},
          {"four-bar", [] { return fourBar(); }},
          {"swung arm", swungArm},
          {"cantilever", cantilever},
          {"portal", portal},
          {"manipulator", manipulator},
          {"slider-crank (SPACAR95)", sliderCrankS95},
          {"cross-spring pivot (spatial)", crossSpringPivot},
          {"gravity cantilever", gravityCantilever}};
}

}  // namespace flexmb::core::samples
