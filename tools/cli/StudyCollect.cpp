// flexmb study collect: the variants' summaries joined into the study's table, report and plots.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>
#include <map>

#include "io/pictures/SvgPlot.hpp"
#include "io/templates/StudySummary.hpp"
#include "io/templates/StudyTable.hpp"
#include "tools/cli/StudyCommand.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace flexmb::cli::study {

namespace {

std::map<std::string, std::string> readKeyValues(const std::string& path) {
  std::map<std::string, std::string> kv;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    const auto c = line.find(": ");
    if (c == std::string::npos) continue;
    const std::string key = line.substr(0, c);
    const bool seen = kv.count(key) > 0;
    std::string& value = kv[key];
    if (seen) value += '\n';  // piecewise: GCC 12's -Wrestrict (tools/README.md)
    value += line.substr(c + 2);
  }
  return kv;
}

std::string fileSafe(const std::string& s) {
  std::string o;
  for (char c : s) o += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ? c : '_';
  return o;
}

}  // namespace

// Joins the variants' summaries into <dir>/study_summary.csv, study_report.html and one SVG per
// quantity and parameter. Variants without a finished summary of the current study are "missing".
int collect(const std::string& dir, std::vector<std::string> plot, bool quiet) {
  const auto setup = readKeyValues((fs::path(dir) / "study.txt").string());
  if (!setup.count("stem")) {
    std::cerr << "flexmb: " << dir << " is not a study folder (no study.txt; `flexmb study` writes it)\n";
    return kInputError;
  }
  const std::string stem = setup.at("stem");
  std::ifstream vin((fs::path(dir) / "variants.csv").string());
  std::vector<io::StudyRecord> records;
  int missing = 0;
  try {
    std::string line;
    if (!std::getline(vin, line)) throw std::runtime_error((fs::path(dir) / "variants.csv").string() + ": empty");
    const auto header = io::splitCsvLine(line);
    while (std::getline(vin, line)) {
      if (line.empty()) continue;
      const auto cells = io::splitCsvLine(line);
      if (cells.size() != header.size() || header.size() < 3)
        throw std::runtime_error((fs::path(dir) / "variants.csv").string() + ": a row does not match the header");
      analysis::Variant v;
      v.number = std::stoi(cells[0]);
      v.name = cells[1];
      for (size_t i = 3; i < cells.size(); ++i) v.values.emplace_back(header[i], std::stod(cells[i]));
      const std::string prefix = (fs::path(variantFolder(dir, v.name)) / stem).string();
      // Finished for this study: its manifest names the fingerprint the study gave the variant.
      const auto manifest = readKeyValues(prefix + "_run.txt");
      const auto fp = manifest.find("fingerprint");
      std::optional<io::StudyRecord> summary;
      if (fp != manifest.end() && fp->second == cells[2]) {
        try {
          summary = io::readStudyRecord(prefix + "_summary.csv");
        } catch (const std::exception&) {  // unsynced files after a power failure: missing, runs again
        }
      }
      if (summary) {
        summary->variant = v.number;
        records.push_back(std::move(*summary));
      } else {
        io::StudyRecord r = analysis::failedRecord(v, "not run yet");
        r.status = "missing";
        records.push_back(std::move(r));
        ++missing;
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kInputError;
  }
  if (plot.empty() && setup.count("plot")) plot = splitList(setup.at("plot"), ' ');
  io::StudyReport report;
  report.title = "Study of " + fs::path(setup.at("template")).filename().string();
  report.lines.push_back("template: " + setup.at("template"));
  if (setup.count("analysis"))
    for (const auto& l : splitList(setup.at("analysis"), '\n')) report.lines.push_back("analysis: " + l);
  for (const std::string& key : accuracyKeys())  // --accuracy / --error-estimate: the study's mesh and its error
    if (setup.count(key))
      for (const std::string& line : splitList(setup.at(key), '\n')) report.lines.push_back(key + ": " + line);
  if (setup.count("command")) report.lines.push_back("command: " + setup.at("command"));
  report.quantities = plot;
  const auto quantities = plot.empty() ? io::plottableQuantities(records) : plot;
  try {
    io::OutputSet files((fs::path(dir) / "study").string());
    files.setSync(false);  // made again from the variants by `flexmb study collect` at any time
    files.checkWritable();
    {
      std::ofstream f(files.temporaryFor("_summary.csv"));
      io::writeStudyTable(f, records);
      writeChecked(f, files.prefix() + "_summary.csv");
    }
    writeText(files, "_report.html", io::renderStudyReport(report, records));
    std::vector<std::string> params;
    if (!records.empty())
      for (const auto& [n, v] : records.front().parameters) params.push_back(n);
    for (const auto& q : quantities)
      for (const auto& p : params) {
        std::string suffix = "_";
        suffix.append(fileSafe(q)).append("_vs_").append(fileSafe(p)).append(".svg");
        io::writeSvg(files.temporaryFor(suffix), io::studyPlot(records, q, p));
      }
    files.setting("command", "study collect");
    for (const std::string& key : accuracyKeys())
      if (setup.count(key))
        for (const std::string& line : splitList(setup.at(key), '\n')) files.setting(key, line);
    files.setting("variants", std::to_string(records.size()));
    files.setting("missing", std::to_string(missing));
    files.commit(missing ? "incomplete: " + std::to_string(missing) + " variants not run yet" : "complete");
    if (!quiet)
      std::cout << "wrote " << files.prefix() << "_summary.csv and " << files.prefix() << "_report.html ("
                << records.size() << " variants" << (missing ? ", " + std::to_string(missing) + " not run yet" : "")
                << ")\n";
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  return kOk;
}

int runCollect(const std::vector<std::string>& args) {
  ModelOptions m;
  std::string plot;
  po::options_description d("options");
  d.add_options()("plot", po::value(&plot),
                  "quantities to plot, comma-separated (default: the study's --plot, else all)")(
      "quiet,q", po::bool_switch(&m.quiet), "print nothing but errors");
  if (auto rc = parseCommand(args, d, m, "usage: flexmb study collect folder [--plot q1,q2,...]")) return *rc;
  return collect(m.file, splitList(plot, ','), m.quiet);
}

}  // namespace flexmb::cli::study
