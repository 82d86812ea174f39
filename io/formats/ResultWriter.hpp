#pragma once
// Result writers: what a time simulation produced (core::Trajectory), in three forms.
//   * writeCsv: one wide CSV table per quantity, columns named by node / element and component.
//   * writeMat: a MATLAB v5 .mat file with SPACAR's variable names (docs/theory/dat-format.md section 5).
//   (The end-of-run state as a restart input is io/formats/RestartWriter.)
//
// Every writer checks its input before writing anything: vector sizes must match the model
// (nx / ne), and every value must be finite (a NaN or Inf throws, naming the quantity, the time and
// the column). Write failures (cannot open the file, short write, matio failure) throw
// std::runtime_error naming the path and the reason. Numbers are formatted locale-independently.
// A refined model with Model::unrefined (`--refine N`) is written at its original nodes and elements
// (io/formats/OriginalResults.hpp): the columns and variables of the model as read.
#include <string>
#include <vector>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/model/Model.hpp"

namespace flexmb::io {

// The MAT-file header text of every MAT file flexmb writes: fixed, so that the same results give
// the same bytes whichever front end wrote them (matio's default holds the time of writing).
inline constexpr const char* kMatHeader = "MATLAB 5.0 MAT-file, Platform: flexmb, Created by: flexmb";

// Column names of the nodal coordinates (size nx): "node3.x", "node3.y", "node103.angle".
std::vector<std::string> coordinateColumnNames(const core::Model& model);
// Column names of the deformations (size ne): "PLBEAM5.e1_elongation", "PLBEAM5.e2_bending_p", ...
// (element keyword and label, 1-based deformation index, the deformation's name with every
// character other than a letter, digit or '_' replaced by '_').
std::vector<std::string> deformationColumnNames(const core::Model& model);

// One wide CSV table per quantity: <prefix>_x.csv, _xd, _xdd (nodal coordinates) and _e, _ed, _edd,
// _sig (deformations). One row per output time; the first column is "time". Numbers are written
// with 17 significant digits (like %.17g), so they read back exactly. Returns the paths written,
// in the order x, xd, xdd, e, ed, edd, sig.
std::vector<std::string> writeCsv(const std::string& prefix, const core::Model& model, const core::Trajectory& traj);

// Orientations of the Euler-parameter nodes in user terms (spatial models; empty for planar ones):
// <prefix>_rot.csv with, per orientation node n, the rotation vector node<n>.rx, .ry, .rz (axis
// times angle in rad, angle in [0, pi]) and the rotation matrix node<n>.R11 ... R33 (row by row) from
// the normalised Euler parameters. Returns the path written, or "" when the model has no such node.
std::string writeOrientationCsv(const std::string& prefix, const core::Model& model, const core::Trajectory& traj);
bool hasOrientationNodes(const core::Model& model);

// A matrix as CSV: a header row "<corner>,<colNames...>", then per row its name and the values
// (17 significant digits). Throws std::invalid_argument on a size mismatch or a non-finite value,
// std::runtime_error naming the path when writing fails.
void writeMatrixCsv(const std::string& path, const Eigen::MatrixXd& A, const std::vector<std::string>& rowNames,
                    const std::vector<std::string>& colNames, const std::string& corner = "");

// MATLAB v5 .mat file (matio, MAT_FT_MAT5, uncompressed) with SPACAR's variable names:
// time (nt x 1), x, xd, xdd (nt x nx), e, ed, edd, sig (nt x ne), nsteps, nfailed, nfevals (1 x 1);
// after a bdf run also njacevals, nlinsetups (1 x 1).
// All double. Rows are output times (SPACAR layout). Spatial models add the orientations of their
// Euler-parameter nodes: rotnodes (1 x nr labels), rotvec (nt x 3 nr: rotation vectors, node by
// node) and rotmat (nt x 9 nr: each node's R(:), column-major, so reshape(rotmat(k, 9*i-8:9*i), 3, 3)
// is node i's rotation matrix at time k).
void writeMat(const std::string& path, const core::Model& model, const core::Trajectory& traj);

// Mode 3: the linearised matrices along a trajectory (Eq. 15) as m x m x nt arrays M0, K0, G0, C0,
// D0, N0 (M0(:,:,k) belongs to time(k)), with time (nt x 1) and freq (nt x nev, Hz). Checks sizes
// and finiteness first (std::invalid_argument naming the matrix and time).
void writeLinearizedMat(const std::string& path, const std::vector<double>& time,
                        const std::vector<core::LinearizedSystem>& sys, const std::vector<Eigen::VectorXd>& omega);

}  // namespace flexmb::io
