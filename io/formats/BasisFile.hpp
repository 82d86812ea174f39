#pragma once
// Reduction basis files (q = V eta, Boer et al. 2013 Eq. 17/20): the matrix V together with a record
// of how it was made, so a basis can be inspected (spreadsheet, MATLAB, Python) and reused.
//
// Format: plain text CSV, '\n' line ends (a '\r' before '\n' is accepted on reading).
//   # flexmb basis                      <- required first line (magic)
//   # method: svd-modal                 <- BasisInfo::method
//   # model: models/guidance.dat        <- BasisInfo::model
//   # size: 17 x 6                      <- rows x columns of V (written always; checked if present)
//   # <key>: <value>                    <- one line per BasisInfo::parameters entry, in order
//   # large: 0 3                        <- BasisInfo::large, blank separated (line always written)
//   # singular values: 0.61 0.25 ...    <- BasisInfo::scaledSingularValues (omitted when empty)
//   0.1,0,...                           <- one row per coordinate q_i: V(i, 0), ..., V(i, m-1)
// Numbers are written like %.17g (locale-independent std::to_chars), so doubles read back bitwise
// equal (including -0 and subnormals). Header lines are "# key: value": key and value are trimmed of
// blanks on reading; the reserved keys are method, model, size, large and singular values; every
// other key is a parameter.
//
// Reading is strict and never crashes on bad input: readBasis / parseBasis throw std::runtime_error
// "<file>:<line>: <reason>" for an empty file, a missing magic line, a header line that is not
// "# key: value", a duplicate key, a header line after the data rows, an empty field, a field that
// is not a finite number, a ragged row, no data rows, a size line that disagrees with the data, and
// large indices that are out of range, repeated, more than the columns, or whose columns are not the
// unit vectors (V's column j < n_l must be e_{large[j]}, as assembleBasis makes it). Blank lines
// are ignored. A missing method/model line reads as an empty string.
//
// Writing validates first and throws std::invalid_argument (nothing is written) for an empty V,
// non-finite entries, an empty method, strings that contain a line break or leading/trailing blanks
// (they would not read back), parameter keys that are empty, contain ':' or are reserved, and
// large indices that do not fit V as above. I/O failures throw std::runtime_error naming the path.
#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace flexmb::io {

struct BasisInfo {
  std::string method;                                           // "modal", "svd-modal", ...
  std::string model;                                            // model file the basis was made for
  std::vector<std::pair<std::string, std::string>> parameters;  // e.g. {"r", "4"}, {"a", "1"}
  std::vector<int> large;                // coordinates with identity columns (column j <-> large[j])
  Eigen::VectorXd scaledSingularValues;  // sigma_k / sum(sigma) for SVD-modal; empty otherwise
};

void writeBasis(const std::string& path, const Eigen::MatrixXd& V, const BasisInfo& info);
Eigen::MatrixXd readBasis(const std::string& path, BasisInfo* info = nullptr);
// readBasis, and its rows must be the model's degrees of freedom (else std::runtime_error naming
// the file and both counts): what every front end's --basis / basis= reads.
Eigen::MatrixXd readBasisFor(const std::string& path, int degreesOfFreedom);

// The same on strings: formatBasis returns the file content; parseBasis uses `name` as the file
// name in its messages.
std::string formatBasis(const Eigen::MatrixXd& V, const BasisInfo& info);
Eigen::MatrixXd parseBasis(const std::string& text, const std::string& name, BasisInfo* info = nullptr);

}  // namespace flexmb::io
