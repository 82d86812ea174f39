#include "analysis/ModelJob.hpp"

#include <tuple>

#include "io/formats/BasisFile.hpp"

namespace flexmb::analysis {

ModelJob::ModelJob(const ModelSource& source) : file_(source.file) {
  try {
    stages_ = readStages(source);
  } catch (const std::exception& e) {  // io::DatError names the file and line
    refuse(e.what());
  }
}

void ModelJob::say(Diagnostic::Kind kind, std::string text, std::string where) {
  diagnostics_.push_back({kind, std::move(where), std::move(text), "", ""});
}

bool ModelJob::refuse(std::string text, std::string where) {
  say(Diagnostic::Kind::Error, std::move(text), std::move(where));
  status_ = JobStatus::InputError;
  return false;
}

void ModelJob::fail(std::string text) {
  say(Diagnostic::Kind::Error, std::move(text), file_);
  status_ = JobStatus::Failed;
}

std::string userFunctionRefusal(const core::Model& model, const std::string& file) {
  for (const auto& [name, line, key] : {std::tuple{model.userStressFunction, model.userStressLine, "USERSIG"},
                                        std::tuple{model.userInputFunction, model.userInputLine, "USERINP"}})
    if (!name.empty())
      return file + ":" + std::to_string(line) + ": " + key + " " + name +
             ": MATLAB user functions drive dynamics only (mode 1 through spacar() in Octave or MATLAB); for this "
             "analysis give the loads and inputs as time expressions (XFT, ESIGT, INPUTXT, INPUTET)";
  return "";
}

ModelSource sourceOfModel(const core::Model& model) {
  auto one = std::make_shared<std::vector<io::AnalysisStage>>(1);
  one->front().model = model;
  one->front().runs = true;
  return {model.sourceFile, {}, std::move(one), nullptr};
}

bool ModelJob::checkModel(const core::Model& model, const ModelNeeds& needs, bool userFunctionsAllowed) {
  if (!userFunctionsAllowed)
    if (std::string why = userFunctionRefusal(model, file_); !why.empty()) return refuse(std::move(why));
  for (Diagnostic& d : checkModelFor(model, file_, needs)) diagnostics_.push_back(std::move(d));
  if (!hasError(diagnostics_)) return true;
  status_ = JobStatus::InputError;
  return false;
}

bool ModelJob::readBasis(const core::Model& model, const BasisInput& input, std::optional<Eigen::MatrixXd>& basis) {
  basis.reset();
  if (!input.file.empty()) {
    try {
      basis = io::readBasisFor(input.file, model.numDofs());
    } catch (const std::exception& e) {
      return refuse(e.what());
    }
  } else if (input.matrix) {
    if (input.matrix->rows() != model.numDofs())
      return refuse("the basis has " + std::to_string(input.matrix->rows()) + " rows; the model has " +
                    std::to_string(model.numDofs()) + " degrees of freedom");
    basis = input.matrix;
  }
  return true;
}

JobStatus ModelJob::finish(bool completed, bool interrupted, const std::string& analysis, const std::string& stopReason,
                           const std::string& kept) {
  if (interrupted) {
    say(Diagnostic::Kind::Error, analysis + " " + stopReason + " (" + kept + ")");
    return status_ = JobStatus::Interrupted;
  }
  if (!completed) {
    say(Diagnostic::Kind::Error, analysis + " stopped: " + stopReason + " (" + kept + ")");
    return status_ = JobStatus::Stopped;
  }
  return status_ = JobStatus::Completed;
}

}  // namespace flexmb::analysis
