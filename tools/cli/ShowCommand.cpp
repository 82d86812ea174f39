// flexmb show: the undeformed model as SVG with node and element numbers and roles, to check a
// model before running it.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>

#include "analysis/ModelCheck.hpp"
#include "io/formats/DatReader.hpp"
#include "io/pictures/MechanismSvg.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Visuals.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
std::string joined(const std::vector<std::string>& v, size_t shown) {
  std::string s;
  for (size_t i = 0; i < std::min(shown, v.size()); ++i) s += (i ? ", " : "") + v[i];
  if (v.size() > shown) s += " and " + std::to_string(v.size() - shown) + " more";
  return s;
}
}  // namespace

int runShow(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  std::string out, viewName, html;
  const std::string htmlHelp =
      std::string("also write the model as a 3-D page to rotate and zoom in a browser (default <model>_model.html)") +
      kHtmlUrlOptions;
  d.add_options()("out,o", po::value(&out), "SVG file to write (default: <model>_model.svg in the current folder)")(
      "html", po::value(&html)->implicit_value("<model>_model.html"), htmlHelp.c_str());
  addViewOption(d, viewName, "xy for planar, iso for spatial models");
  if (auto rc = parseCommand(
          args, d, m, "usage: flexmb show model.dat [--out picture.svg] [--view xy|xz|yz|iso] [--html [page.html]]"))
    return *rc;
  io::ModelDrawing drawing;
  drawing.view = viewNamed(viewName);
  core::Model model;
  if (!loadModel(m, model)) return kInputError;
  if (out.empty()) out = std::filesystem::path(m.file).stem().string() + "_model.svg";
  // A name without an extension gets `.svg`: a browser or viewer does not open a bare name.
  if (!std::filesystem::path(out).has_extension()) out += ".svg";
  if (html == "<model>_model.html") html = std::filesystem::path(m.file).stem().string() + "_model.html";
  // The output folder is checked before the work, as every command does (README: exit codes).
  if (const auto folder = std::filesystem::path(out).parent_path();
      !folder.empty() && !std::filesystem::is_directory(folder)) {
    std::cerr << "flexmb: cannot write '" << out << "': the folder '" << folder.string() << "' does not exist\n";
    return kInputError;
  }

  drawing.title = std::filesystem::path(m.file).filename().string() + " (" + io::dialectName(model.dialect) + ")";
  bool wellPosed = true;
  const analysis::ModelCheck check = analysis::checkModel(model);
  if (check.kinematicsError.empty()) {
    const core::KinematicReport& r = check.kinematics;
    std::vector<std::string> dofs;
    for (const auto& q : model.dofs)
      dofs.push_back(q.isDeformation ? model.deformationName(q.index) : model.coordName(q.index));
    drawing.notes.push_back(std::to_string(r.positionNodes) + " position and " + std::to_string(r.orientationNodes) +
                            " orientation nodes, " + std::to_string(r.elements) + " elements; " +
                            std::to_string(r.dof) + " degrees of freedom");
    if (!dofs.empty()) drawing.notes.push_back("DOF: " + joined(dofs, 4));
    wellPosed = r.wellPosed();
    if (wellPosed) {
      drawing.notes.push_back("kinematic check: well posed");
    } else {
      if (!r.underdetermined.empty())
        drawing.notes.push_back("kinematic check: UNDER-DETERMINED, free motion in " + joined(r.underdetermined, 4));
      if (!r.overdetermined.empty())
        drawing.notes.push_back("kinematic check: OVER-DETERMINED, redundant " + joined(r.overdetermined, 4));
    }
  } else {
    drawing.notes.push_back("kinematic check failed: " + check.kinematicsError);
    wellPosed = false;
  }
  try {
    const io::MechanismGeometry geometry(model);
    io::writeModelSvg(out, geometry, drawing);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  std::cout << "wrote " << out << "\n";
  if (!html.empty() && !writeModelPage(html, model, drawing.title)) return kWriteFailed;
  // The manifest beside the picture (<picture>_run.txt), as every command that writes files has.
  try {
    io::OutputSet files((std::filesystem::path(out).parent_path() / std::filesystem::path(out).stem()).string());
    files.setting("command", "show");
    recordModel(files, m, model);
    files.setting("view", viewName.empty() ? "auto" : viewName);
    files.record(out);
    if (!html.empty()) files.record(html);
    std::cout << "wrote " << files.writeManifest("complete") << "\n";
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  if (!wellPosed)
    std::cerr << "flexmb: the kinematic check found problems (see the notes in the picture, or run flexmb check)\n";
  return 0;
}

}  // namespace flexmb::cli
