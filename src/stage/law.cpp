#include "stage/law.hpp"

#include "core/error.hpp"
#include "fit/fit.hpp"
#include "io/atomic_output.hpp"
#include "io/hash.hpp"
#include "io/law_file.hpp"
#include "io/sweep_file.hpp"

namespace dualcell::stage {

law::Law run_fit(const std::filesystem::path& sweep_file, const std::filesystem::path& out) {
  io::check_outputs({out}, {sweep_file});
  const io::SweepHeader header = io::read_sweep_header(sweep_file);
  const std::vector<sweep::PathResult> paths = io::read_sweep(sweep_file);
  law::Law law = fit::fit_law(paths, header);
  law.provenance.sweep_file = sweep_file.string();
  law.provenance.sweep_hash = io::file_hash(sweep_file);
  io::write_law(out, law);
  return law;
}

namespace {

std::string describe(const law::Law& law, law::ExportFormat format, const std::string& name) {
  switch (format) {
    case law::ExportFormat::json:
      return "JSON, " + std::to_string(law.directions.size()) + " directions";
    case law::ExportFormat::csv:
      return "CSV, " + std::to_string(law.directions.size()) + " rows";
    case law::ExportFormat::calculix:
      return "CalculiX, materials " + name + "_TENSION and " + name + "_COMPRESSION";
    case law::ExportFormat::umat:
      return "user material ABAQUS_" + name + " for dualcell's umat";
  }
  return "";
}

}  // namespace

std::string export_law(const ExportOptions& options) {
  io::check_outputs({options.out}, {options.law_file});
  const law::Law law = io::read_law(options.law_file);
  std::string text;
  switch (options.format) {
    case law::ExportFormat::json:
      text = law::law_json(law);
      break;
    case law::ExportFormat::csv:
      text = law::law_csv(law);
      break;
    case law::ExportFormat::calculix:
      text = law::law_calculix(law, options.name, options.law_file.string());
      break;
    case law::ExportFormat::umat:
      text = law::law_umat(law, options.name, options.law_file.string());
      break;
  }
  io::write_output(options.out, text);
  return describe(law, options.format, options.name);
}

}  // namespace dualcell::stage
