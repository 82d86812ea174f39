#pragma once
// Reduced-operator files (issue 33): the fitted fields of core::ReducedOperators beside a basis
// file (`flexmb reduce` writes basis.csv and basis.operators; `simulate --basis basis.csv` reads
// them), plain text:
//   # flexmb reduced operators            <- required first line
//   # <key>: <value>                      <- provenance and fit quality (dofs, basis checksum,
//                                            model checksum (16 hex digits), tolerance, force error,
//                                            mass error, output error, force scale, mass scale,
//                                            damping scale, load scale, training samples,
//                                            validation samples, training seconds, operator
//                                            seconds, equation 19 seconds, range)
//   load XFT 12                           <- a time-dependent load: keyword, x or e index (0-based)
//   output x 12                           <- a tracked output: x (nodal coordinate) or e, index (0-based)
//   matrix <name> <rows> <cols>           <- then `rows` lines of `cols` comma-separated numbers:
//                                            centre, rotation, lower, upper, potential, mass,
//                                            damping, loadFields, outputFields, heldOut (the
//                                            held-out configurations); `ints exponents <rows> <cols>`
// Numbers are written as %.17g (they read back bitwise). Reading is strict: "<file>:<line>: <reason>"
// for a missing magic line, an unknown key or block, a malformed or non-finite number, a ragged
// or short block, and blocks whose sizes do not fit each other.
#include <string>

#include "core/model/ReducedOperatorData.hpp"

namespace flexmb::io {

std::string formatOperators(const core::ReducedOperators& ops);
core::ReducedOperators parseOperators(const std::string& text, const std::string& name);

void writeOperators(const std::string& path, const core::ReducedOperators& ops);
core::ReducedOperators readOperators(const std::string& path);

// The operator file beside a basis file: basis.csv -> basis.operators.
std::string operatorPathFor(const std::string& basisPath);

}  // namespace flexmb::io
