#include "stage/export.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/text.hpp"
#include "fit/fit.hpp"
#include "io/atomic_output.hpp"
#include "io/law_file.hpp"
#include "io/points_csv.hpp"
#include "io/sweep_file.hpp"
#include "law/cell_text.hpp"
#include "law/form.hpp"

namespace dualcell::stage {

namespace {

std::string describe(const law::Law& law, io::ExportFormat format, const std::string& name) {
  switch (format) {
    case io::ExportFormat::json:
      return "JSON, " + std::to_string(law.directions.size()) + " directions";
    case io::ExportFormat::csv:
      return "CSV, " + std::to_string(law.directions.size()) + " rows";
    case io::ExportFormat::calculix:
      return "CalculiX, materials " + name + "_TENSION and " + name + "_COMPRESSION";
    case io::ExportFormat::umat:
      return "user material ABAQUS_" + name + " for dualcell's umat";
  }
  return "";
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The largest error a compact law may have to be exported, and how a message names it: the
// option where given, else the tolerance the law was fitted to.
struct ErrorLimit {
  double value;
  std::string name;
};
ErrorLimit error_limit(const ExportOptions& options, const law::Law& law) {
  if (!std::isnan(options.max_law_error)) return {options.max_law_error, "--max-law-error"};
  if (std::isfinite(law.small_fit.tolerance)) return {law.small_fit.tolerance, "the law's fit tolerance"};
  return {fit::default_law_tolerance, "the default tolerance"};
}

// A compact law whose measured error passes the limit is not exported (unless --force).
void refuse_over_error(const ExportOptions& options, const ErrorLimit& limit, const std::string& what,
                       const law::ConeCheck& c) {
  if (options.force || c.directions.empty() || c.max_error <= limit.value) return;
  char text[400];
  std::snprintf(text, sizeof text,
                " misses %s by %.1f %% of stress at sxx,syy,sxy = %.3f,%.3f,%.3f, more than %s %.3g %%: "
                "not exported (--force writes it anyway)",
                law::checked_against_text(c.against), 100 * c.max_error, c.worst(0), c.worst(1), c.worst(2),
                limit.name.c_str(), 100 * limit.value);
  throw InputError(options.law_file.string() + ": " + what + text);
}

}  // namespace

std::string export_law(const ExportOptions& options) {
  if (!options.form.empty() && options.format != io::ExportFormat::umat)
    throw InputError("--form " + options.form + ": only for --format umat (the other formats carry the fitted laws)");
  if (!options.breaks.empty() && options.breaks != "within" && options.breaks != "between")
    throw InputError("--breaks " + options.breaks + ": must be \"within\" or \"between\"");
  io::check_outputs({options.out}, {options.law_file});
  const law::Law law = io::read_law(options.law_file);
  const bool umat = options.format == io::ExportFormat::umat;
  // The umat's form (the other formats carry every form law.h5 has).
  const law::LawForm form = umat ? law::pick_form(law, options.form, options.law_file.string()) : law::LawForm::cone;
  const bool small = umat && form == law::LawForm::small;
  if (!options.breaks.empty() && (!umat || form == law::LawForm::cone))
    throw InputError("--breaks " + options.breaks + ": only for --format umat of a cell (--form cell or small)");
  if (options.stress_free_temperature && (!umat || form == law::LawForm::cone))
    throw InputError("--stress-free-temperature: only for --format umat of a cell (--form cell)");
  const ErrorLimit limit = error_limit(options, law);
  // The small cell is vouched for by its check against the exact law, as the cone-wise law is.
  if (small) refuse_over_error(options, limit, "the small cell", law.small_check);
  // And the small cell of the whole ply by its check along six-component strain paths.
  const law::PlyCheck& ply = law.small_ply_check;
  if (small && ply.directions > 0 && !options.force && !(ply.max_error <= limit.value))
    throw InputError(options.law_file.string() + ": the small cell of the whole ply misses the exact law along " +
                     std::to_string(ply.directions) + " six-component strain paths by " +
                     formatted("%.1f", 100 * ply.max_error) + " % of stress, more than " + limit.name + " " +
                     formatted("%.3g", 100 * limit.value) + " %: not exported (--force writes it anyway)");
  if (umat && form != law::LawForm::cone) {
    const law::CondensedCell& cell = io::umat_cell(law, form, options.law_file.string());
    // Two files, committed together: the card and the cell it names.
    const std::filesystem::path cell_file = options.out.parent_path() / io::umat_cell_file(options.cell_id);
    io::check_outputs({options.out, cell_file}, {options.law_file});
    std::ostringstream cell_text;
    law::write_cell_text(cell_text, cell);
    const std::uint64_t cell_hash = text_hash_value(cell_text.str());
    // Another cell under the same id: a card written before names that file (by its hash, which
    // the umat checks), so replacing it would break that card's analysis, unless that card is
    // the one --out replaces now (a rerun writes both again).
    if (!options.force && std::filesystem::is_regular_file(cell_file)) {
      const std::string old_cell = read_text(cell_file);
      const std::uint64_t old_hash = text_hash_value(old_cell);
      const bool card_replaced_too =
          std::filesystem::is_regular_file(options.out) &&
          std::filesystem::file_size(options.out) < (std::uintmax_t{1} << 20) &&
          read_text(options.out).find(io::umat_cell_hash_constants(old_hash)) != std::string::npos;
      if (old_hash != cell_hash && !card_replaced_too)
        throw InputError(cell_file.string() +
                         ": holds another cell (a card written before names it by its hash): "
                         "choose another --cell-id, or --force to replace it");
    }
    const std::string card =
        io::law_umat_cell(law, form, options.name, options.cell_id, cell_hash, options.law_file.string(),
                          options.breaks == "between" ? io::UmatBreaks::between : io::UmatBreaks::within,
                          options.stress_free_temperature);
    io::AtomicOutputs outputs;
    outputs.add(options.out);
    outputs.add(cell_file);
    outputs.write(options.out, card);
    outputs.write(cell_file, cell_text.str());
    outputs.commit();
    return "user material ABAQUS_" + options.name + " for dualcell's umat, " +
           (small ? "the small cell (" : "the exact law (") + std::to_string(cell.n_rows()) +
           (small ? " rows) in " : " interface rows) in ") + cell_file.string();
  }
  std::string text;
  switch (options.format) {
    case io::ExportFormat::json:
      text = io::law_json(law);
      break;
    case io::ExportFormat::csv:
      text = io::law_csv(law);
      break;
    case io::ExportFormat::calculix:
      text = io::law_calculix(law, options.name, options.law_file.string());
      break;
    case io::ExportFormat::umat: {
      // The umat carries the law past the fuse where the law has an onset surface: both checked,
      // and a law that was not measured at all (no exact law, one direction) is not vouched for.
      if (!options.force && law.cone.ok && law.cone_check.directions.empty())
        throw InputError(options.law_file.string() +
                         ": the cone-wise law was measured neither against an exact law nor on held-out "
                         "sweep directions (" +
                         (law.cell_note.empty() ? std::string("the sweep has one direction") : law.cell_note) +
                         "): not exported (--force writes it anyway)");
      refuse_over_error(options, limit, "the cone-wise law", law.cone_check);
      refuse_over_error(options, limit, "the cone-wise law after the fuse", law.cone_after_fuse_check);
      text = io::law_umat(law, options.name, options.law_file.string());
      break;
    }
  }
  io::write_output(options.out, text);
  return describe(law, options.format, options.name);
}

}  // namespace dualcell::stage
