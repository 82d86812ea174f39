#pragma once
// The one table of .dat keywords (docs/theory/dat-format.md): name, dialect(s), block, argument layout and
// meaning. It drives the reader (argument counts, types and messages), `flexmb keywords`
// (printKeywords) and the unknown-keyword suggestions. Element keywords come from
// core::elementTypes(); SPACAR keywords flexmb does not support are listed too, so that they are
// reported as "not supported by flexmb yet" rather than as unknown.
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "core/elements/Element.hpp"

namespace flexmb::io {

// Which dialects know a keyword (bit set). Used for dialect detection.
enum DialectBits : unsigned { kSpacar95 = 1u, kSpacar2013 = 2u, kBothDialects = 3u };

// Where a keyword may appear. Kinematic: the first block (before the first END). Dynamic: any later
// block. Structure: END, HALT, EOF, VISUALIZATION (block structure, handled by the reader itself).
// Anywhere: any block (OUTLEVEL, which SPACAR Light writes at the top of the file; the settings of a
// SPACAR95 restart state). In a SPACAR95 file the first block may also hold Dynamic keywords.
// Transfer: the mode-9 transfer block after the dynamic block's END HALT (INPUTF, OUTX, ...).
enum class BlockKind { Kinematic, Dynamic, Structure, Anywhere, Transfer };

enum class ArgType {
  Node,        // node label: positive integer
  Element,     // element label: positive integer
  Component,   // 1-based component index: positive integer
  Count,       // positive integer (number of steps, iterations, ...)
  Integer,     // non-negative integer (control fields that may be 0)
  Word,        // any token (the arguments of settings flexmb accepts and ignores)
  Real,        // real number (E or Fortran D exponent)
  Expression,  // quoted muParser expression in t (section 6)
  Name,        // a MATLAB function name: a letter, then letters, digits, '_' (USERSIG, USERINP)
};

enum class Cardinality { One, Optional, Many };  // Optional/Many only at the end of a layout

struct ArgSpec {
  ArgType type = ArgType::Real;
  std::string name;    // shown in messages: "node p", "EA", "x(t)"
  std::string symbol;  // shown in the synopsis: "p1", "EA", "\"x(t)\""
  Cardinality card = Cardinality::One;
  // For ArgType::Node: the node kind the slot requires, when it fixes one (element slots, XY, BETA).
  enum class Kind { Any, Position, Orientation, Warping } kind = Kind::Any;
};

// What the reader does with a statement.
enum class Action {
  Element,
  Coordinates,
  CoordinatesXY,
  CoordinatesBeta,
  ReferenceCoordinates,  // XREF (flexmb extension: a spatial restart's element references)
  Fix,
  InputXRole,
  DynX,
  DynE,
  Rlse,
  InputERole,
  LumpedMass,
  ElementInertia,
  Stiffness,
  Damping,
  Force,
  ForceIncrement,
  Gravity,
  InputXValues,
  InputEValues,
  XD,
  XDD,
  E,
  ED,
  EDD,
  StartDE,
  InputIncrement,
  Prestress,
  TimeStep,
  EpsInt,
  ErrorTol,
  HMax,
  EpsKin,
  MaxIterat,
  IterStep,
  Time,
  TimeForce,
  TimeStress,
  Reference,
  InputXFunctions,
  InputEFunctions,
  UserStress,
  UserInput,
  OutLevel,
  Length0,
  Ignored,
  End,
  Halt,
  Eof,
  Visualization,
  Transfer,  // a mode-9 transfer input or output (INPUTF, INX, OUTF, OUTX, OUTXP)
  Unsupported,
};

struct KeywordInfo {
  std::string name;  // upper case, at most 8 characters (VISUALIZATION excepted)
  unsigned dialects = kBothDialects;
  BlockKind block = BlockKind::Dynamic;
  Action action = Action::Unsupported;
  std::vector<ArgSpec> args;    // argument layout (SPACAR 2013+ order where the dialects differ)
  std::vector<ArgSpec> args95;  // SPACAR95 layout when it differs (TIMESTEP n T), else empty
  std::string meaning;
  bool extension = false;                              // flexmb extension (docs/theory/dat-format.md section 6)
  const core::ElementTypeInfo* elementType = nullptr;  // for Action::Element
  std::string unsupportedNote;                         // for Action::Unsupported: what to do instead
  bool transfer = false;                               // a mode-9 transfer-block keyword (INPUTF, OUTX, ...)

  // The layout in force for a file of the given dialect (spacar95: args95 when set).
  const std::vector<ArgSpec>& layout(bool spacar95) const;
  // "expected 5 integers (element, node p, orientation p, node q, orientation q)": the count,
  // noun and argument names of a layout, without the "found" part.
  static std::string expectation(const std::vector<ArgSpec>& layout);
  static int minArgs(const std::vector<ArgSpec>& layout);
  static int maxArgs(const std::vector<ArgSpec>& layout);  // -1: unbounded
  // Syntax for the keyword list, "PLBEAM e p1 o1 p2 o2" style.
  static std::string synopsis(const std::string& name, const std::vector<ArgSpec>& layout);
};

// The whole table (built once, includes the element keywords of core::elementTypes()).
const std::vector<KeywordInfo>& keywordTable();

// All entries named `name` (case-insensitive): INPUTX and INPUTE have one per block.
std::vector<const KeywordInfo*> findKeywords(std::string_view name);
// The entry for `name` usable in `block`, or nullptr (none by that name, or only for another block).
const KeywordInfo* findKeyword(std::string_view name, BlockKind block);

// The known keyword nearest to `unknown` by edit distance, or "" when nothing is close.
std::string suggestKeyword(std::string_view unknown);

// Case-insensitive Levenshtein distance (exposed for tests).
int editDistance(std::string_view a, std::string_view b);

// `flexmb keywords`: the table as text, grouped by block, with dialects and meanings.
void printKeywords(std::ostream& out);

// `flexmb keywords --markdown`: the .dat language reference (io/dat-language.md), generated from
// the table so that it cannot drift (a test compares the committed file with this text).
void printKeywordsMarkdown(std::ostream& out);

}  // namespace flexmb::io
