#pragma once
// Reads a SPACAR .dat file (dat-format.md sections 1-4 and 6, both dialects) into a core::Model.
//
// Block structure (one rule for both dialects):
//   * The first block is the kinematic block (elements, coordinates, roles); it ends with END.
//   * HALT directly after the kinematic block's END is a separator (SPACAR 2013+ writes END HALT).
//   * Every later block is a dynamic/static block (SPACAR95 may have several), each closed by END.
//   * The input ends, after a block's END, at: another END (an empty block: SPACAR 2013+'s END END),
//     HALT (after a dynamic block), EOF, VISUALIZATION, or the end of the file. Whatever follows is
//     not read.
//   * The end of the file (or EOF / VISUALIZATION / a misplaced HALT) inside an open block is an
//     error: "missing END". A file without statements is an error.
//   * A keyword is only accepted in its block (an element keyword after the kinematic END is an
//     error naming the block it belongs to). INPUTX and INPUTE mean roles in the kinematic block and
//     values (x [v [a]]) in a dynamic block.
//
// Dialect: from the keywords used (SPACAR95-only versus 2013-only, see KeywordTable); neither gives
// SPACAR 2013+; both is an error naming one keyword of each. ReadOptions::dialect skips detection
// (and the mixing check): it only decides the dialect-dependent readings (TIMESTEP field order,
// PLBEAM elongation).
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/Model.hpp"

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
  std::optional<core::Dialect> dialect;                   // overrides detection
  std::optional<core::ElongationDefinition> elongation;   // overrides the PLBEAM default
};

// The elongation definition PLBEAM gets for a dialect: SPACAR95 Plain, 2013+ BendingCorrected.
core::ElongationDefinition defaultElongation(core::Dialect d);

const char* dialectName(core::Dialect d);  // "SPACAR95" / "SPACAR 2013+"

core::Model readDatFile(const std::string& path, const ReadOptions& options = {});
core::Model readDatString(std::string_view text, const std::string& virtualFileName = "<string>",
                          const ReadOptions& options = {});

// The dialect a text would be read in (detection only; throws DatError on mixing or lexical errors).
core::Dialect detectDialect(std::string_view text, const std::string& virtualFileName = "<string>");

}  // namespace flexmb::io
