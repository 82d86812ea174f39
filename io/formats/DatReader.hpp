#pragma once
// Reads a SPACAR .dat file (docs/theory/dat-format.md sections 1-4 and 6, both dialects) into a core::Model.
//
// Block structure:
//   * A file is a sequence of blocks, each closed by END. SPACAR 2013+ writes the kinematic block,
//     END HALT, the dynamic/static block, END END (mode 9 adds a transfer block: END HALT, INPUTF /
//     OUTX / ..., END END, read into the last stage's Model::transferInputs / transferOutputs and
//     checked against the roles, errors with file:line). SPACAR95 writes
//     blocks closed by END up to EOF; its first block may hold every keyword at once.
//   * The input ends, after a block's END, at: another END (an empty block), HALT (after a later
//     block, unless a transfer block follows), EOF, VISUALIZATION, or the end of the file.
//   * The end of the file (or EOF / VISUALIZATION / a misplaced HALT) inside an open block is an
//     error: "missing END". A file without statements is an error.
//   * SPACAR 2013+: kinematic keywords in the first block only, dynamic ones after it; INPUTX and
//     INPUTE mean roles in the first block and values (x [v [a]]) after it. SPACAR95: the first
//     block takes every keyword; a later block takes dynamic keywords and restated roles (FIX,
//     INPUTX, DYNE, ... always roles in SPACAR95), not elements or coordinates.
//   * Analysis stages: at each END the model as read so far is finalised into an AnalysisStage.
//     A stage whose block gives TIMESTEP runs an analysis over its period (SPACAR95: TIMESTEP n Tp
//     from the current time TIME, default 0; 2013+: TIMESTEP T n up to the end time T); the next
//     block continues from its end: the current time advances to the end time and the inputs given
//     by value and rate (x + v (t - TIME) + a (t - TIME)^2/2) restart from their values there.
//     Initial values (E, ED, EDD, STARTDE) after a stage that ran are an error: the state carries
//     over (the analysis floor's stage chain).
// Dialect: from the keywords used (SPACAR95-only versus 2013-only, see KeywordTable); neither gives
// SPACAR 2013+; both is an error naming one keyword of each. ReadOptions::dialect skips detection
// (and the mixing check): it only decides the dialect-dependent readings (TIMESTEP field order,
// PLBEAM elongation).
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::io {

// Every reading error: file, line (0 when none applies, e.g. a file that cannot be opened or is
// empty), keyword ("" when none) and the message proper. what() is
// "file.dat:12: PLBEAM: expected 5 integers (element, node p, orientation p, node q, orientation q),
// found 4".
class DatError : public std::runtime_error {
 public:
  DatError(std::string file, int line, std::string keyword, std::string message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& keyword() const { return keyword_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_;
  std::string keyword_;
  std::string message_;
};

struct ReadOptions {
  std::optional<core::Dialect> dialect;                  // overrides detection
  std::optional<core::ElongationDefinition> elongation;  // overrides the PLBEAM default
  int refine = 1;  // every flexible beam split in this many elements (io/formats/MeshRefinement.hpp)
  // With refine > 1: results of the refined model's every node and element (Model::unrefined left
  // null); false: at the original nodes and elements under their labels (io/formats/OriginalResults.hpp).
  bool refinedResults = false;
};

// The elongation definition PLBEAM gets for a dialect: SPACAR95 Plain, 2013+ BendingCorrected.
core::ElongationDefinition defaultElongation(core::Dialect d);

const char* dialectName(core::Dialect d);  // "SPACAR95" / "SPACAR 2013+"

// One analysis stage: the model as read up to an END (all stages share the topology).
struct AnalysisStage {
  core::Model model;
  bool runs = false;  // the block gave TIMESTEP: an analysis runs over [settings.t0, settings.tEnd]
  int endLine = 0;    // the END that closed the block
};

// The file's text, read in one open (throws DatError: no such file, a directory, unreadable).
std::string readDatText(const std::string& path);

// Every stage of a file, in order (at least one).
std::vector<AnalysisStage> readDatStages(const std::string& path, const ReadOptions& options = {});
std::vector<AnalysisStage> readDatStagesString(std::string_view text, const std::string& virtualFileName = "<string>",
                                               const ReadOptions& options = {});

// The model of the last stage (everything the file gives), for analyses without stages.
core::Model readDatFile(const std::string& path, const ReadOptions& options = {});
core::Model readDatString(std::string_view text, const std::string& virtualFileName = "<string>",
                          const ReadOptions& options = {});

// The dialect a text would be read in (detection only; throws DatError on mixing or lexical errors).
core::Dialect detectDialect(std::string_view text, const std::string& virtualFileName = "<string>");

}  // namespace flexmb::io
