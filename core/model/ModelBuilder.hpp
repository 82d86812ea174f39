#pragma once
// Builds an immutable Model from statements in any order (the .dat reader's target).
// Every call carries the source line; errors are ModelError(line, message).
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::core {

class ModelError : public std::runtime_error {
 public:
  ModelError(int line, const std::string& message) : std::runtime_error(message), line_(line) {}
  int line() const { return line_; }

 private:
  int line_;
};

class ModelBuilder {
 public:
  explicit ModelBuilder(std::string sourceFile);
  ~ModelBuilder();

  // Kinematic block. Node kinds are fixed by the first element slot that uses a node.
  void addElement(const ElementTypeInfo& type, int label, std::span<const int> nodeLabels, int line);
  // Spatial elements with a direction vector (BEAM ... y1 y2 y3, HINGE ... a1 a2 a3).
  void addElement(const ElementTypeInfo& type, int label, std::span<const int> nodeLabels,
                  std::span<const double> vector, int line);
  void setCoordinates(int node, std::span<const double> values, int line);  // X, XY, BETA
  // XREF (flexmb extension, written by spatial restart echoes): the node's coordinates in the
  // configuration the elements are created in (their undeformed reference), when X gives another.
  void setReferenceCoordinates(int node, std::span<const double> values, int line);
  void setCoordinateRole(int node, std::span<const int> comps, Role role, int line);  // 1-based; empty = all
  void setDeformationRole(int element, std::span<const int> comps, Role role, int line);

  // Dynamic / static block.
  void setLumpedMass(int node, double value, int line);                     // MASS / XM
  void setElementInertia(int element, double rhoA, double rhoI, int line);  // EMASS / EM
  // EM with the element type's layout (planar rhoA [rhoI]; BEAM rhoA Jxx Jyy Jzz Jyz).
  void setElementInertia(int element, std::span<const double> values, int line);
  // XM on a spatial orientation node: Ixx Ixy Ixz Iyy Iyz Izz (body frame), or one value (I * 1).
  void setNodeInertia(int node, std::span<const double> values, int line);
  void setStiffness(int element, std::span<const double> params, int line);
  void setDamping(int element, std::span<const double> params, int line);
  void addForce(int node, std::span<const double> comps, int line);           // FORCE / XF
  void addForceIncrement(int node, std::span<const double> comps, int line);  // DELXF
  void addTimeForce(int node, int comp, TimeFunctionPtr f, int line);         // XFT
  void setGravity(double gx, double gy, int line);
  void setGravity(double gx, double gy, double gz, int line);
  // Input coordinate values: 2013+ INPUTX n i x [v [a]]; SPACAR95 XD / XDD set one field each.
  void setInputCoordinate(int node, int comp, std::optional<double> x, std::optional<double> v, std::optional<double> a,
                          int line);
  void setInputCoordinateFunctions(int node, int comp, TimeFunctionPtr x, TimeFunctionPtr v, TimeFunctionPtr a,
                                   int line);  // INPUTXT
  void setInputDeformationFunctions(int element, int comp, TimeFunctionPtr x, TimeFunctionPtr v, TimeFunctionPtr a,
                                    int line);  // INPUTET
  // Input deformation values e(t) = x + v t + a t^2/2 (dynamic-block INPUTE e i x [v [a]], by
  // analogy with INPUTX; SPACAR95's E/ED/EDD on an input deformation do the same through
  // setInitialDeformation). Default x = 0 (the reference configuration).
  void setInputDeformation(int element, int comp, std::optional<double> x, std::optional<double> v,
                           std::optional<double> a, int line);
  void setInputIncrement(int node, int comp, double delta, int line);  // DELINPX
  void setInitialDeformation(int element, int comp, std::optional<double> e, std::optional<double> ed,
                             std::optional<double> edd, int line);  // E/ED/EDD, STARTDE
  // ESIG e s1 [s2 ... sn]: the prestress of the element's deformations in their order (values left
  // off at the end are 0; a later ESIG for the element replaces the row). Resolved in finalize():
  // flexmb's former ESIG e 1 s on an element with one deformation is read with a note; more values
  // than deformations are an error; two values on an element with more deformations whose first is
  // a deformation number (the former ESIG e i s) are read as SPACAR reads them, with a warning.
  void setPrestress(int element, std::span<const double> values, int line);
  // EM / ESTIFF / EDAMP / ESIG with the element number and no values (oopspa writes such lines for
  // elements without the property): nothing is set, as if the line were absent. The element must
  // exist; one note per keyword names the lines.
  void noValues(const std::string& keyword, int element, int line);
  // SPACAR95 XD: the rate of an input coordinate, or the initial rate of a DYNX coordinate.
  void setCoordinateRate(int node, int comp, double v, int line);
  // SPACAR95 XDD: the acceleration of an input coordinate; on a DYNX coordinate (SPACAR95's echo of
  // an end state writes it) it is accepted and not used: the equations of motion give it.
  void setCoordinateAcceleration(int node, int comp, double a, int line);
  // LENGTH0 (a SPACAR95 restart state): the reference length of an element. Any LENGTH0 makes the
  // model a restart state (Model::restartState): X is the current configuration, the deformations
  // there are E (0 where not given), and element references are derived from them.
  void setReferenceLength(int element, double length0, int line);
  void addNote(std::string note);  // Model::notes (a note given twice is kept once)
  void addTimeStress(int element, int comp, TimeFunctionPtr f, int line);  // ESIGT
  void setReference(int element, int comp, TimeFunctionPtr f, int line);   // EREF

  AnalysisSettings& settings();
  void setDialect(Dialect d);

  // Validates (every referenced node and element defined, parameters consistent) and freezes.
  Model finalize(const ElementOptions& options);

 private:
  struct Impl;
  struct Finalizer;  // finalize() in its phases (ModelBuilder.cpp)
  std::unique_ptr<Impl> impl_;
};

}  // namespace flexmb::core
