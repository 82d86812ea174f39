#pragma once
// Where a job's model comes from, read once, and the checks every analysis makes before it runs,
// returned as data (Diagnostic) that each front end shows in its own way: the command line on
// stderr, Python as exceptions and warnings, spacar() as MATLAB warnings and errors.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/model/Model.hpp"
#include "io/formats/DatReader.hpp"

namespace flexmb::analysis {

// One message of a job. `where` is the file it is about (empty: the program's own voice, shown as
// "flexmb"); the text names no front end's spelling of an option.
struct Diagnostic {
  enum class Kind {
    Result,   // a result line (stdout)
    Note,     // left out by --quiet
    Warning,  // legal, but probably not what was meant
    Error     // before the run: an input error (the job cannot go on); after it: why it stopped
  };
  Diagnostic() = default;
  Diagnostic(Kind k, std::string w, std::string t, std::string s = "", std::string tp = "", std::string o = "")
      : kind(k),
        where(std::move(w)),
        text(std::move(t)),
        see(std::move(s)),
        topic(std::move(tp)),
        options(std::move(o)) {}
  Kind kind = Kind::Note;
  std::string where;
  std::string text;
  // An analysis that tells more ("check": the kinematic rank analysis of mode 0), which the front end
  // names in its own spelling (`flexmb check`, flexmb.check, spacar(0, name)); empty: none.
  std::string see;
  // What a result line is ("statistics", "wall time"), for a front end that words it its own way.
  std::string topic;
  // The options that change what the text says to change, by their Python names, comma-separated
  // ("max_step", "reltol,abstol"); each front end adds its own spelling (`--max-step`, opts.maxstep,
  // max_step=). Empty: none.
  std::string options;
};
using Diagnostics = std::vector<Diagnostic>;
bool hasError(const Diagnostics& d);
// The text with its options in a front end's spelling: "text (option --max-step)", "text (options
// --reltol, --abstol)"; spell maps a Python name to the front end's ("" leaves it out).
std::string withOptions(const Diagnostic& d, const std::function<std::string(const std::string&)>& spell);
// The first error's text, "where: text" (empty: none), its options spelled by `spell` (none: left out).
std::string firstError(const Diagnostics& d, const std::function<std::string(const std::string&)>& spell = {});

// A model file and how to read it, or the stages of one already read (a Python Model, a study
// variant): a job reads the file exactly once. read.refine splits the flexible beams of either
// (io/formats/MeshRefinement.hpp; given stages are taken as read without it).
struct ModelSource {
  std::string file;
  io::ReadOptions read;
  std::shared_ptr<const std::vector<io::AnalysisStage>> stages;  // given: `file` only names them
  std::shared_ptr<const std::string> text;                       // the file's text, already read (`file` names it)
};

// The stages of the source: the given ones, the given text parsed, or the file read once. Throws io::DatError (file,
// line, what is wrong) or std::runtime_error.
std::shared_ptr<const std::vector<io::AnalysisStage>> readStages(const ModelSource& source);

// SPACAR's mode 3 on a file without TIMESTEP (a static file: ITERSTEP load steps) linearises its
// load steps; with TIMESTEP, the trajectory.
bool isStaticFile(const std::vector<io::AnalysisStage>& stages);

// What an analysis needs of its model before it starts.
struct ModelNeeds {
  bool mass = false;  // dynamics and eigenfrequencies: mass on every degree of freedom
  bool degreesOfFreedom = true;
  bool allowDriven = false;  // a driven rigid mechanism (no degrees of freedom, moving inputs) is fine
};

// The file's notes and warnings, then the checks that make an analysis meaningless (overflowing
// values, no degrees of freedom, an initial assembly on another branch, massless degrees of freedom),
// as diagnostics; an Error among them means the analysis must not run.
Diagnostics checkModelFor(const core::Model& model, const std::string& file, const ModelNeeds& needs);

}  // namespace flexmb::analysis
