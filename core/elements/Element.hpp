#pragma once
// Narrow element interface (paper Eq. 1-5): deformations e = D(x) of one element, their
// derivatives, constitutive matrices and inertia. One class per element type implements it.
#include <Eigen/Core>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace flexmb::core {

// Capacity of the largest element: the spatial BEAMW (two position nodes of 3 coordinates, two
// orientation nodes of 4 Euler parameters, two warping nodes of 1; eight deformations).
constexpr int kMaxElemCoords = 16;
constexpr int kMaxElemDefs = 8;
// Fixed-capacity Eigen types: no heap allocation in element kernels (hot path).
using ElemVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxElemCoords, 1>;
using DefVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxElemDefs, 1>;
using DefJac = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxElemDefs, kMaxElemCoords>;
using ElemMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxElemCoords, kMaxElemCoords>;
using DefMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxElemDefs, kMaxElemDefs>;

// Planar models: Position (x y) and Orientation (angle). Spatial models: SpatialPosition (x y z),
// EulerParameters (lambda0..lambda3, normalised by the automatic L2MIN1 constraint) and Warping
// (one coordinate: the rate of twist dphi/ds of BEAMW's cross-section, rad per length; default 0;
// a degree of freedom unless FIX or INPUTX says otherwise, core/elements/BEAMW.md).
enum class NodeKind { Position, Orientation, SpatialPosition, EulerParameters, Warping };
constexpr int nodeKindDim(NodeKind k) {
  switch (k) {
    case NodeKind::Position:
      return 2;
    case NodeKind::Orientation:
      return 1;
    case NodeKind::SpatialPosition:
      return 3;
    case NodeKind::EulerParameters:
      return 4;
    case NodeKind::Warping:
      return 1;
  }
  return 0;
}
constexpr bool isTranslational(NodeKind k) { return k == NodeKind::Position || k == NodeKind::SpatialPosition; }
constexpr bool isSpatial(NodeKind k) {
  return k == NodeKind::SpatialPosition || k == NodeKind::EulerParameters || k == NodeKind::Warping;
}
// Coordinates that are rotations (angle, Euler parameters); a warping coordinate is not one.
constexpr bool isRotational(NodeKind k) { return k == NodeKind::Orientation || k == NodeKind::EulerParameters; }

// How the PLBEAM elongation is defined: SPACAR95's l - l0, or Eq. 3a with the bending correction.
enum class ElongationDefinition { Plain, BendingCorrected };

struct ElementOptions {
  ElongationDefinition elongation = ElongationDefinition::BendingCorrected;
};

// Distributed inertia of an element (EMASS / EM): mass and rotary inertia per unit length.
// Spatial elements use rhoA and the per-length mass moments of inertia of the cross-section about
// its local x (polar), y, z axes and the product yz (EM rhoA Jxx Jyy Jzz Jyz); BEAMW adds the
// warping inertia per length jw = rho Cw (EM ... Jw).
struct ElementInertia {
  double rhoA = 0.0;
  double rhoI = 0.0;
  double jxx = 0.0, jyy = 0.0, jzz = 0.0, jyz = 0.0;
  double jxy = 0.0, jxz = 0.0;  // full tensor of a rigid body on an orientation node (XM)
  double jw = 0.0;
  bool any() const {
    return rhoA != 0.0 || rhoI != 0.0 || jxx != 0.0 || jyy != 0.0 || jzz != 0.0 || jyz != 0.0 || jxy != 0.0 ||
           jxz != 0.0 || jw != 0.0;
  }
  // The field an EM parameter of the registry's inertia layout fills, by its name ("rhoA", "Jxx",
  // "Jyy", "Jzz", "Jyz", "Jw"); null for a name without one.
  static double ElementInertia::*field(std::string_view name);
};

// Whether an element's deformation measure still describes the configuration (see
// Element::validity). Plain data, no allocation: checked at every output time of a simulation.
struct ElementValidity {
  bool valid = true;
  int slot = -1;                // the offending node, as slot index in keyword order
  double rotation = 0.0;        // its rotation (rad) that left the valid range
  const char* limit = nullptr;  // static text after "rotated N degrees": the assumption it breaks
};

class Element {
 public:
  virtual ~Element() = default;
  virtual int numCoords() const = 0;
  virtual int numDeformations() const = 0;

  // e = D(x), Eq. 1.
  virtual void deformations(const ElemVec& x, DefVec& e) const = 0;
  // De = dD/dx (numDeformations x numCoords).
  virtual void jacobian(const ElemVec& x, DefJac& De) const = 0;
  // d2_i = v^T (d^2 D_i / dx^2) v: the convective contraction D2e[v,v].
  virtual void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const = 0;
  // H = sum_i sigma_i d^2 D_i / dx^2 (geometric stiffness, Eq. 16c).
  virtual void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const = 0;

  // e and De together: the kinematics need both at every iterate, and an element whose two share
  // their geometry (chord, sines of the node angles) computes it once. Same values as the two calls.
  virtual void deformationsAndJacobian(const ElemVec& x, DefVec& e, DefJac& De) const {
    deformations(x, e);
    jacobian(x, De);
  }

  // Closed-form inverse of e = D(x) for open chains (solved in one pass, without iteration): the
  // coordinates form two ends; given one end and all deformations e, place() writes the other end
  // (`to`: 0 or 1) into x and returns false where e has no solution on the element's valid branch.
  // endOfCoordinate(i): the end of local coordinate i, -1 for an element without a closed form.
  virtual int endOfCoordinate(int i) const {
    (void)i;
    return -1;
  }
  virtual bool place(const DefVec& e, int to, ElemVec& x) const {
    (void)e, (void)to, (void)x;
    return false;
  }

  // Constitutive matrix from ESTIFF/EDAMP parameters (same layout for stiffness and damping).
  virtual void constitutive(std::span<const double> params, DefMat& S) const = 0;

  // Consistent, configuration dependent mass matrix M_e(x); zero when the element carries none.
  virtual void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const {
    (void)inertia;
    M.setZero(x.size(), x.size());
  }
  // Velocity dependent inertia forces h_e(x, xd): M_e xdd + h_e is the inertia force.
  virtual void velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemVec& h) const {
    (void)xd, (void)inertia;
    h.setZero(x.size());
  }
  // M_e, h_e and the convective D2e[xd, xd] together (the equations of motion need all three at
  // every evaluation); same values as mass(), velocityForces() and secondDerivative().
  virtual void dynamicTerms(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemMat& M, ElemVec& h,
                            DefVec& d2) const {
    mass(x, inertia, M);
    velocityForces(x, xd, inertia, h);
    secondDerivative(x, xd, d2);
  }
  // Nodal forces of gravity g = (gx, gy) acting on the distributed mass.
  virtual void gravityForces(const ElemVec& x, const ElementInertia& inertia, double gx, double gy, ElemVec& f) const {
    (void)inertia, (void)gx, (void)gy;
    f.setZero(x.size());
  }
  // Gravity g = (gx, gy, gz); planar elements ignore gz.
  virtual void gravityForces3(const ElemVec& x, const ElementInertia& inertia, const double* g, ElemVec& f) const {
    gravityForces(x, inertia, g[0], g[1], f);
  }

  // Whether the deformation measure is valid at x. An element whose e = D(x) is exact for any
  // rigid motion and any deformation (truss, hinge) is always valid; the beam is not (Eq. 3b/3c
  // measure bending as l0 sin theta, which folds back beyond 90 degrees).
  virtual ElementValidity validity(const ElemVec& x) const {
    (void)x;
    return {};
  }
  // Reference (undeformed) length l0, 0 for an element without one (hinge). Written as LENGTH0.
  virtual double referenceLength() const { return 0.0; }
  // The element triad in the body frame of its end-th orientation node (keyword order: 0 the first,
  // 1 the second): columns e_x (along the chord; a hinge's axis), e_y, e_z; the current triad is
  // R(lambda) A (docs/theory/spatial-elements.md 1.4). The `.sbd` rxyz (end 0) and rxyzq (end 1), and the
  // cross-sections of the pictures. False for an element without a triad there.
  virtual bool elementFrame(int end, Eigen::Matrix3d& A) const {
    (void)end, (void)A;
    return false;
  }
  // Its own displacement field, for the pictures (io/pictures/MechanismGeometry): the centre line at x in
  // points.cols() points at xi = k / (n - 1) from its first to its last position node and, when ys
  // and zs are given (sized like points), the section's local y and z axes there. False for an
  // element without a field of its own: it is drawn straight between its position nodes.
  virtual bool centreLine(const ElemVec& x, Eigen::Ref<Eigen::Matrix3Xd> points, Eigen::Matrix3Xd* ys = nullptr,
                          Eigen::Matrix3Xd* zs = nullptr) const {
    (void)x, (void)points, (void)ys, (void)zs;
    return false;
  }
  // True for a deformation that is an angle known only modulo 2 pi (a spatial hinge's rotation,
  // a principal value): the kinematics keep it continuous along the motion.
  virtual bool isPeriodicAngle(int /*i*/) const { return false; }
  // Restart reference (SPACAR95 LENGTH0): re-derives the reference geometry so that the element's
  // deformations at x are e, with reference length length0 when > 0. Throws std::invalid_argument
  // for an element type that does not support it.
  virtual void setReference(const ElemVec& x, const DefVec& e, double length0) {
    (void)x, (void)e, (void)length0;
    throw std::invalid_argument("this element type does not support a restart reference (LENGTH0)");
  }
};

// One entry of the element keyword table: drives the .dat reader, `flexmb keywords` and docs.
struct ParameterSpec {
  std::string name;
  std::string unit;
  std::string meaning;
};

// What a deformation measures (the registry says it per deformation): analyses that read section
// forces go by it (the analysis floor's design studies), not by the deformation's name. Beams
// measure torsion and bending as l0 times an angle, so their generalised stresses are moments over l0.
enum class DeformationKind { Elongation, Torsion, Bending, BendingY, BendingZ, Rotation, Warping, Other };

struct ElementTypeInfo {
  std::string keyword;  // e.g. "PLBEAM"
  std::string description;
  std::vector<NodeKind> slots;  // node kinds in keyword order
  std::vector<std::string> deformationNames;
  std::vector<ParameterSpec> stiffness;  // ESTIFF / EDAMP layout
  // Creates the element from its initial nodal coordinates (reference geometry l0, beta0).
  std::unique_ptr<Element> (*create)(const ElemVec& x0, const ElementOptions& options);
  // Spatial elements with a direction vector after the nodes (BEAM ... y1 y2 y3: the initial
  // cross-section y axis; HINGE ... a1 a2 a3: the axis). create is then unused.
  std::vector<ParameterSpec> vector = {};
  std::unique_ptr<Element> (*createWithVector)(const ElemVec& x0, const double* v,
                                               const ElementOptions& options) = nullptr;
  // EM layout when it differs from the planar "rhoA [rhoI]".
  std::vector<ParameterSpec> inertia = {};
  // ESTIFF values that must be given (the rest of the layout may be left off and is 0): BEAMW's
  // 7, so that a file without the warping stiffness is an error instead of a silent E Cw = 0.
  int requiredStiffness = 0;
  // Trailing ESTIFF / EM values other programs write for this element and flexmb reads and ignores
  // with a note (SPACAR Light and oopspa write one section layout, BEAMW's, for every beam and truss).
  std::vector<ParameterSpec> ignoredStiffness = {}, ignoredInertia = {};
  // Deformations (0-based) that are always released (calculable) and carry stress when the element
  // has ESTIFF: BEAMW's warping deformations 7 and 8. RLSE on them is accepted; DYNE, INPUTE are errors.
  std::vector<int> alwaysReleased = {};
  bool internal = false;  // created by flexmb (L2MIN1), not a user keyword
  // SPACAR's element type code: the `.sbd` variable `it` that SPACAR's viewer (spadraw) and stress
  // tool (stressbeam) read; io/results.md lists the codes and where they come from.
  int spacarTypeId = 0;
  // Deformations (0-based) that are large rotations, such as a hinge's angle: a DYNE one keeps an
  // identity column in a reduction basis (the q_l of Eq. 21, analysis::defaultLargeCoordinates).
  std::vector<int> largeRotations = {};
  // Drawn as the curve of its displacement field instead of straight lines between its position
  // nodes (io/pictures/MechanismGeometry): planar (p, phi_p, q, phi_q) from the bending deformations (the
  // planar beam's cubic, PlanarBeam.hpp); spatial (p, lambda_p, q, lambda_q) as the cubic through
  // the end triads R(lambda) elementFrame.
  bool drawnCurved = false;
  // One per deformation (deformationNames' order); missing ones are Other.
  std::vector<DeformationKind> deformationKinds = {};
  DeformationKind deformationKind(int deformation) const {
    return deformation < static_cast<int>(deformationKinds.size()) ? deformationKinds[deformation]
                                                                   : DeformationKind::Other;
  }
  int numCoords() const;
  int numDeformations() const { return static_cast<int>(deformationNames.size()); }
  bool isLargeRotation(int deformation) const;
  bool isAlwaysReleased(int deformation) const;
};

// The registry (one list, in ElementRegistry.cpp). Keyword lookup is case-insensitive.
const std::vector<ElementTypeInfo>& elementTypes();
const ElementTypeInfo* findElementType(std::string_view keyword);
// L2MIN1, the automatic normalisation element of orientation nodes (not in the keyword registry).
const ElementTypeInfo& normalisationType();

}  // namespace flexmb::core
