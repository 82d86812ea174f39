#pragma once
// The immutable model (Pinocchio-style): topology, parameters, coordinate roles, loads and
// analysis settings. Built once by ModelBuilder; all state lives in workspaces of the algorithms.
#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/elements/Element.hpp"
#include "core/model/TimeFunction.hpp"
#include "core/model/UserFunctions.hpp"

namespace flexmb::core {

enum class Dialect { Spacar95, Spacar2013 };

// Role of a nodal coordinate or a deformation in the kinematic equations (docs/develop/design.md).
// Nodal coordinates default to Calculable, deformations default to Fixed.
enum class Role { Fixed, Input, Dynamic, Calculable };
const char* roleName(Role r);

struct Node {
  int label = 0;
  NodeKind kind = NodeKind::Position;
  int firstCoord = 0;  // index into x
  int dim() const { return nodeKindDim(kind); }
  int line = 0;  // where it was first used
};

struct ElementEntry {
  int label = 0;
  const ElementTypeInfo* type = nullptr;
  std::shared_ptr<const Element> impl;
  std::vector<int> nodes;   // node indices (into Model::nodes), keyword order
  std::vector<int> coords;  // global x indices of the element's nodal coordinates, in order
  int firstDef = 0;         // index of the element's first deformation in e
  int line = 0;
  ElementInertia inertia;
  bool hasStiffness = false, hasDamping = false;
  std::vector<double> stiffnessParams, dampingParams;  // as given (ESTIFF / EDAMP), for echoes
  std::vector<double> inertiaParams;                   // as given (EM / EMASS), for result files
  std::vector<double> vec;  // the element line's vector as given (BEAM's y1 y2 y3, HINGE's axis), for echoes
  DefMat S, Sd;             // constitutive stiffness and damping (ndef x ndef)
  // The element's entries of a global nodal vector (positions, velocities, forces ...).
  void gather(const Eigen::VectorXd& v, ElemVec& out) const {
    out.resize(static_cast<int>(coords.size()));
    for (size_t j = 0; j < coords.size(); ++j) out[j] = v[coords[j]];
  }
};

// A prescribed value in time: polynomial x0 + v t + a t^2/2, or three expressions.
struct Rheonomic {
  int index = 0;  // x index (input coordinate) or e index (input deformation)
  double x0 = 0.0, v = 0.0, a = 0.0;
  TimeFunctionPtr fx, fv, fa;  // when set, replace the polynomial
  double delta = 0.0;          // DELINPX: TOTAL increment over the static load steps
  double tRef = 0.0;           // time origin of the polynomial: x0 + v (t - tRef) + a (t - tRef)^2/2
  double base = 0.0;           // the coordinate's X (0 for a deformation): where the initial-load
                               // ramp of a static analysis starts (x = base + s (x0 - base))
  void evaluate(double t, double& x, double& xd, double& xdd) const;
};

struct TimeLoad {
  int index = 0;  // x index (XFT) or e index (ESIGT, EREF)
  TimeFunctionPtr f;
};

struct LumpedMass {
  int coord = 0;  // x index
  double value = 0.0;
};

// A moment on a spatial orientation node in global components (XF n Mx My Mz, SPACAR 2017+):
// its generalised force on the Euler parameters is 2 E(lambda)^T M (docs/theory/spatial-elements.md 6.3).
struct NodalMoment {
  int node = 0;                                         // node index
  Eigen::Vector3d value = Eigen::Vector3d::Zero();      // XF
  Eigen::Vector3d increment = Eigen::Vector3d::Zero();  // DELXF, scaled like delf
};

// One channel of the mode-9 transfer block (INPUTF, INX, OUTX, OUTXP, OUTF k n i), resolved by
// the reader against the model's roles (io/dat-language.md says which coordinates each accepts).
struct TransferChannel {
  enum class Kind {
    Force,       // INPUTF: a force on a free coordinate (spatial orientation node: a global moment)
    Motion,      // INX: the prescribed motion of an input coordinate (position, velocity, acceleration)
    Coordinate,  // OUTX: a coordinate (spatial orientation node: the rotation about a global axis)
    Velocity,    // OUTXP: its rate
    NodalForce,  // OUTF: the force a fixed or input coordinate takes (fxt)
  };
  Kind kind = Kind::Force;
  int number = 0;     // k: the channel's place among the inputs or the outputs (1-based)
  int node = 0;       // node index
  int component = 0;  // i (1-based)
  int coord = 0;      // x index of the coordinate (spatial orientation node: its first Euler parameter)
  bool axis = false;  // spatial orientation node: i is a global axis, the channel a moment or rotation
  int line = 0;       // where the block names it
  std::string keyword;
};

// Drawing hints of an element from the file's VISUALIZATION section (SPACAR Light writes BEAMPROPS /
// CROSSTYPE / CROSSDIM, GRAPHICS / FACECOLOR / OPACITY and DONOTDRAW): pictures only, no mechanics
// reads them.
struct ElementAppearance {
  enum class Section { Unknown, Rectangle, Circle };
  Section section = Section::Unknown;
  double width = 0.0;      // rectangle: along the local y axis; circle: the diameter
  double thickness = 0.0;  // rectangle: along the local z axis
  bool hasColor = false;
  double color[3] = {0.0, 0.0, 0.0};  // FACECOLOR, 0..1
  double opacity = 1.0;
  bool hidden = false;  // DONOTDRAW
};

struct AnalysisSettings {
  double t0 = 0.0;
  double tEnd = 1.0;
  int outputIntervals = 100;
  double relTol = 1e-3;
  double absTol = 1e-6;
  double hmax = 0.0;            // 0: ode45 default 0.1*|tf - t0|
  double kinematicTol = 1e-12;  // Newton tolerance, relative to the model size (below ode tolerances)
  // EPSKIN or the ITERSTEP tolerance was given. Without it a simulation sets the kinematic
  // tolerance from the integrator's (1e-5 RelTol, at most 1e-10): far below the integration error, no tighter.
  bool kinematicTolGiven = false;
  int maxIterations = 50;
  int loadSteps = 1;              // ITERSTEP field 2: steps of the DEL* increments (total at the last)
  int initialLoadSteps = 0;       // ITERSTEP field 6: steps of the initial loads (0: at once)
  int outputLevel = 0;            // OUTLEVEL a
  int transferFunctionLevel = 0;  // OUTLEVEL .. b: 1 asks for the first-order transfer functions
  bool timestepGiven = false;
};

struct Model {
  std::string sourceFile;
  Dialect dialect = Dialect::Spacar2013;

  std::vector<Node> nodes;
  std::map<int, int> nodeByLabel;
  std::vector<ElementEntry> elements;
  std::map<int, int> elementByLabel;

  int nx = 0;          // number of nodal coordinates
  int ne = 0;          // number of deformations
  Eigen::VectorXd x0;  // initial nodal coordinates (reference configuration)
  // The configuration the element objects were created in (their undeformed reference): x0, except
  // for the nodes a restart echo gives XREF (flexmb extension: a spatial restart's current X and
  // its original reference differ). Size nx.
  Eigen::VectorXd xRef;
  std::vector<Role> xRole;         // size nx
  std::vector<Role> eRole;         // size ne
  std::vector<int> xOwnerNode;     // x index -> node index
  std::vector<int> eOwnerElement;  // e index -> element index

  // Independent coordinates q: DYNX coordinates (in the order the file names them), the warping
  // coordinates no FIX, INPUTX or DYNX names (BEAMW: degrees of freedom by default, in node
  // order), then DYNE deformations (in the order the file names them).
  struct Dof {
    bool isDeformation = false;
    int index = 0;  // x or e index
  };
  std::vector<Dof> dofs;

  // Initial values of dynamic deformations / coordinates (E, ED, STARTDE); NaN where not given.
  Eigen::VectorXd e0, ed0, edd0;
  Eigen::VectorXd xd0;  // initial rates of DYNX coordinates (SPACAR95 XD), size nx; NaN where not given
  // A restart state (the file gives LENGTH0): the coordinates X are the current configuration, the
  // deformations there are E (0 where not given) and reference lengths come from LENGTH0.
  bool restartState = false;
  // Reader notes for the user, each listed once (settings accepted and ignored, blocks not used,
  // statements about nodes no element uses).
  std::vector<std::string> notes;
  // Legal input that is probably a mistake and changes the model (a position node without an X
  // line sits at the origin): shown by every command, `check` included.
  std::vector<std::string> warnings;

  // Loads and stresses.
  Eigen::VectorXd f0;                // constant nodal forces (XF/FORCE), size nx
  Eigen::VectorXd delf;              // DELXF, size nx
  std::vector<TimeLoad> timeForces;  // XFT
  double gravity[3] = {0.0, 0.0, 0.0};
  std::vector<NodalMoment> moments;  // spatial models: global moments on orientation nodes
  bool spatial = false;              // the model's elements are spatial (BEAM, TRUSS, HINGE ...)
  bool hasGravity = false;
  Eigen::VectorXd sigma0;              // ESIG prestress, size ne
  std::vector<TimeLoad> timeStresses;  // ESIGT
  std::vector<TimeLoad> references;    // EREF: sigma = S (e - eref(t))
  std::vector<Rheonomic> inputX;       // prescribed nodal coordinates
  std::vector<Rheonomic> inputE;       // prescribed deformations

  std::vector<LumpedMass> lumpedMasses;
  AnalysisSettings settings;
  // Mode 9: the transfer block's inputs and outputs, each in channel order (empty without one).
  std::vector<TransferChannel> transferInputs, transferOutputs;
  std::map<int, ElementAppearance> appearance;  // by element label: the VISUALIZATION section

  // USERSIG / USERINP: the MATLAB function names the file gives (with their lines), and the
  // implementation a front end sets before an analysis (null: none; the command line rejects them).
  std::string userStressFunction, userInputFunction;
  int userStressLine = 0, userInputLine = 0;
  std::shared_ptr<UserFunctions> userFunctions;

  // A refined model (core/model/Refinement.hpp): the model as read, whose nodes, elements,
  // coordinates [0, nx) and deformations [0, ne) are this one's first. Result writers write at those
  // (io/formats/OriginalResults.hpp); null: not refined, or the refined model's own results asked for.
  std::shared_ptr<const Model> unrefined;

  int numDofs() const { return static_cast<int>(dofs.size()); }
  // Human-readable names for messages: "x(node 3, 2)" and "e(element 5, 3)".
  std::string coordName(int xIndex) const;
  std::string deformationName(int eIndex) const;
  // The model's extent: the largest |x0| of a position coordinate (planar or spatial; 0 when all
  // positions are at the origin). The scale of lengths in tolerances and step sizes.
  double lengthScale() const;
};

}  // namespace flexmb::core
