#pragma once
// SPACAR-shaped results (io/results.md): SPACAR's variables with SPACAR's names and layouts, written
// as MAT v5 files (matio) that Octave's and MATLAB's `load` read and flexmb's getfrsbf serves:
//   <name>.sbd  topology, counts and the data of every stored step;
//   <name>.sbm  the system matrices M0, K0, G0, C0, D0, N0 of every stored step, frequencies, modes.
// SPACAR stores x and e sorted by role; lnp and le map node coordinates and element deformations
// to their places in them:
//   x = [fixed (x^o); calculable (x^c); input (x^m, rheonomic); dynamic (x^m, DYNX)],
//   e = [fixed (e^o); input (e^m, rheonomic); dynamic (e^m, DYNE); released (e^c)],
// nxp and nep count those groups as [fixed, calculable/released, input, dynamic]. Within a group
// the model's order is kept, the dynamic groups in the order of the degrees of freedom q (the rows
// of M0), so that the kinematic degrees of freedom [x^m input, x^m dynamic, e^m input, e^m dynamic]
// are the columns of dx and the dynamic ones in that order are the rows of M0.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/dynamics/ResultQuantities.hpp"
#include "core/model/Model.hpp"

namespace flexmb::io {

struct SpacarLayout {
  std::vector<int> xOrder, xPos;                 // SPACAR place (0-based) -> model x index, and back
  std::vector<int> eOrder, ePos;                 // same for deformations
  int nxp[4] = {0, 0, 0, 0};                     // fixed, calculable, input, dynamic coordinates
  int nep[4] = {0, 0, 0, 0};                     // fixed, released, input, dynamic deformations
  std::vector<core::FreeCoordinate> dofColumns;  // the columns of dx, in order (model indices)
  int ndof() const { return nxp[2] + nxp[3] + nep[2] + nep[3]; }
  int nddof() const { return nxp[3] + nep[3]; }
  Eigen::VectorXd sortX(const Eigen::VectorXd& v) const;  // model order -> SPACAR order
  Eigen::VectorXd sortE(const Eigen::VectorXd& v) const;
  Eigen::VectorXd unsortX(const Eigen::VectorXd& v) const;  // SPACAR order -> model order
};
SpacarLayout spacarLayout(const core::Model& model);

// The topology tables (rows by node / element label, 0 for unused labels; io/results.md):
// lnp (places of node coordinates in x), ln (element nodes), le (places of element deformations in
// e), it (type ids: a row, 1 x elements, as SPACAR's IT), rl0 (reference lengths).
struct SpacarTopology {
  Eigen::MatrixXd lnp, ln, le, it, rl0;
};
SpacarTopology spacarTopology(const core::Model& model, const SpacarLayout& layout);

// rxyz (end 0) and rxyzq (end 1) (io/results.md): row el = the triad of element el at its first
// (second) orientation node, in that node's body frame (columns e_x, e_y, e_z, stored column-wise:
// reshape(rxyz(el, :), 3, 3); Element::elementFrame); zeros for elements without a triad there; 0 x 0
// for planar models.
Eigen::MatrixXd spacarElementTriads(const core::Model& model, Eigen::Index rows, int end = 0);

// esig (io/results.md): row el = the ESIG prestress of element el's deformations (keyword order, as
// le); 0 pads; 0 x 0 when no element has a prestress.
Eigen::MatrixXd spacarElementPrestress(const core::Model& model, Eigen::Index rows);

// The element constants as the file gives them (io/results.md): row el = element el's ESTIFF,
// EDAMP or EM values (trailing ones the file omits and unused labels are 0); at least `minCols`
// columns (stif: 6, as spatools reads the BEAM shear coefficients from columns 5:6).
enum class ElementConstant { Stiffness, Damping, Mass };
Eigen::MatrixXd spacarElementConstants(const core::Model& model, ElementConstant which, Eigen::Index rows,
                                       Eigen::Index minCols = 1);

// Element type id written to `it`: SPACAR's code of the element's type (ElementTypeInfo::spacarTypeId,
// listed in io/results.md); 0 without a type.
int elementTypeId(const core::ElementTypeInfo* type);

struct SpacarStep {
  Eigen::VectorXd x, xd, xdd, fxt;  // nx, SPACAR order
  Eigen::VectorXd fx, fxgrav;       // nx, SPACAR order: applied nodal loads (USERSIG's included) and
                                    // gravity loads; written when every step has them
  Eigen::VectorXd e, ed, edd, sig;  // ne, SPACAR order
  Eigen::MatrixXd dx;               // nx x ndof (rows SPACAR order), when requested
  Eigen::MatrixXd de;               // ne x ndof (rows SPACAR order): D dx, SPACAR's de, with dx
  Eigen::MatrixXd bigd;             // ne x nx (both SPACAR order), when requested
  // System matrices (m x m, m = nddof or the reduced size), when the analysis has them.
  Eigen::MatrixXd M0, K0, G0, C0, D0, N0;
  Eigen::VectorXd freq;          // Hz
  Eigen::MatrixXd modeq, modex;  // mode shapes: in q (m x nev) and in x (nx x nev)
  // Mode 3 on a static file (.ltv): M0 and K0B = K0 + N0 + G0 over every kinematic degree of
  // freedom (ndof x ndof, the columns of dx), when the analysis has them.
  Eigen::MatrixXd M0all, K0B;
};

// Mode 9: the state-space model of the last step (d/dt z = A z + B u, y = C z + D u, z = [dq; dqd]
// in the order of M0's rows), with a name per input and output.
struct SpacarStateSpace {
  Eigen::MatrixXd A, B, C, D;
  std::vector<std::string> inputNames, outputNames;
};

// One variable of a result file, in memory: a double array (column-major data, dims 2 or 3) or a
// char matrix (text, one string per row).
struct SpacarVariable {
  std::string name;
  std::vector<std::size_t> dims;
  std::vector<double> data;
  std::vector<std::string> text;
  bool isText = false;
};
struct SpacarResults {
  int mode = 1;              // SPACAR mode of the analysis (1, 3, 4, 10; 0 kinematic; 2 modes)
  std::vector<double> time;  // per step: time, or the load factor in a static analysis
  std::vector<SpacarStep> steps;
  long nsteps = 0, nfailed = 0, nfevals = 0;  // integrator statistics (mode 1, 3, 4)
  bool completed = true;
  std::string stopReason;
  std::string warning;                         // a completed run that is worth a remark (mode 0 of a model that
                                               // is not uniquely solvable: initial configuration and bigd only)
  std::optional<SpacarStateSpace> stateSpace;  // mode 9
  // Written at the end of the .sbd as they are: what an analysis derives beyond SPACAR's variables
  // (statics: SPACAR Light's stressmax, Freac, Mreac, CMglob; analysis/StaticDesign.hpp).
  std::vector<SpacarVariable> extraSbd;
};

// Writes <base>.sbd and, when a step holds system matrices, frequencies or modes, <base>.sbm; and
// <base>.ltv (SPACAR's linear-model file, read by its getss and by oopspa) with the state-space
// model A, B, C, D, DFT (1 when D is not zero), inputnames, outputnames (mode 9; A .. D also in
// the .sbm), or with M0 and K0B of every step (mode 3). Checks sizes and finiteness first
// (std::invalid_argument naming the variable and step); write failures throw std::runtime_error
// naming the path. Returns the paths written. A refined model with Model::unrefined (`--refine N`)
// is written in its original model's layout (io/formats/OriginalResults.hpp).
std::vector<std::string> writeSpacarResults(const std::string& base, const core::Model& model,
                                            const SpacarResults& results);

struct SpacarFileContents {
  std::string path;  // <base>.sbd, <base>.sbm, <base>.ltv
  std::vector<SpacarVariable> variables;
};
// The files writeSpacarResults writes, with the same variables and checks, in memory (the gateway
// puts them into the workspace whatever happens to the files).
std::vector<SpacarFileContents> spacarResultFiles(const std::string& base, const core::Model& model,
                                                  const SpacarResults& results);
// Writes one of them (MAT v5, as writeSpacarResults); std::runtime_error naming the path on failure,
// after removing what it wrote of the file.
void writeSpacarFile(const SpacarFileContents& file);

}  // namespace flexmb::io
