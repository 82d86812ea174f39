#pragma once
// `flexmb transfer`'s file set (mode 9), one writer for every front end: the state-space matrices
// A, B, C, D as CSV tables, SPACAR's .sbd/.sbm/.ltv, the Bode diagrams (one SVG per input-output
// pair), each made on its own (io::OutputSet::attempt: a failure in a later one keeps the earlier),
// then the manifest.
#include <ostream>
#include <string>
#include <vector>

#include "analysis/Transfer.hpp"
#include "core/model/Model.hpp"
#include "io/formats/OutputFile.hpp"

namespace flexmb::analysis {

struct TransferFiles {
  bool bode = true;                   // draw the Bode diagrams
  bool forceBode = false;             // also for more than kBodeStateLimit states (each frequency an O(n^2) solve)
  std::string modelFile;              // named in the diagrams' titles
  double fminHz = 0.0, fmaxHz = 0.0;  // the diagrams' range (0: from the eigenfrequencies)
  static constexpr long kBodeStateLimit = 400;
};

struct WrittenTransfer {
  std::vector<std::string> paths;  // every file, the manifest last
  bool incomplete = false;         // a product failed (said on err and in the manifest)
};

// Writes the run's files; out gets the notes ("Bode diagrams not drawn ...", the undamped note),
// err the failures. Throws std::runtime_error when the manifest cannot be written.
WrittenTransfer writeTransfer(io::OutputSet& files, const core::Model& model, const TransferRun& run,
                              const TransferFiles& what, std::ostream& out, std::ostream& err);

}  // namespace flexmb::analysis
