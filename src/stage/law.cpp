#include "stage/law.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"
#include "fit/fit.hpp"
#include "io/atomic_output.hpp"
#include "io/hash.hpp"
#include "io/law_file.hpp"
#include "io/points_csv.hpp"
#include "io/sweep_file.hpp"
#include "law/cell_text.hpp"

namespace dualcell::stage {

law::Law run_fit(const std::filesystem::path& sweep_file, const std::filesystem::path& out) {
  io::check_outputs({out}, {sweep_file});
  const io::SweepHeader header = io::read_sweep_header(sweep_file);
  const std::vector<sweep::PathResult> paths = io::read_sweep(sweep_file);
  law::Law law = fit::fit_law(paths, header);
  // The exact law must give back the sweep it came from; one that does not is not written.
  if (law.cell && !law.cell_replay.ok()) {
    const law::CellReplay& c = law.cell_replay;
    char text[300];
    std::snprintf(text, sizeof text,
                  "the exact law misses the sweep's point (path %d, step %d) by %.3g relative, more than %.3g "
                  "(1e3 × the sweep's QP tolerance): the condensation is wrong for this cell",
                  c.worst_path, c.worst_step, c.max_error, c.limit);
    throw InputError(sweep_file.string() + ": " + text);
  }
  law.provenance.sweep_file = sweep_file.string();
  law.provenance.sweep_hash = io::file_hash(sweep_file);
  io::write_law(out, law);
  return law;
}

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

}  // namespace

std::string export_law(const ExportOptions& options) {
  if (!options.form.empty() && options.format != io::ExportFormat::umat)
    throw InputError("--form " + options.form + ": only for --format umat (the other formats carry the fitted laws)");
  if (options.form != "" && options.form != "cell" && options.form != "cone")
    throw InputError("--form " + options.form + ": must be \"cell\" (the exact law) or \"cone\"");
  io::check_outputs({options.out}, {options.law_file});
  const law::Law law = io::read_law(options.law_file);
  const std::string form = options.form.empty() ? (law.cell ? "cell" : "cone") : options.form;
  if (options.format == io::ExportFormat::umat && form == "cell") {
    // Two files, committed together: the card and the cell it names.
    const std::filesystem::path cell_file = options.out.parent_path() / io::umat_cell_file(options.cell_id);
    io::check_outputs({options.out, cell_file}, {options.law_file});
    const std::string card = io::law_umat_cell(law, options.name, options.cell_id, options.law_file.string());
    std::ostringstream cell_text;
    law::write_cell_text(cell_text, *law.cell);
    io::AtomicOutputs outputs;
    outputs.add(options.out);
    outputs.add(cell_file);
    outputs.write(options.out, card);
    outputs.write(cell_file, cell_text.str());
    outputs.commit();
    return "user material ABAQUS_" + options.name + " for dualcell's umat, the exact law (" +
           std::to_string(law.cell->n_rows()) + " interface rows) in " + cell_file.string();
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
      for (const auto* check : {&law.cone_check, &law.cone_after_fuse_check}) {
        const law::ConeCheck& c = *check;
        if (options.force || c.directions.empty() || c.max_error <= options.max_law_error) continue;
        char text_[400];
        std::snprintf(text_, sizeof text_,
                      "the cone-wise law%s misses %s by %.1f %% of stress at sxx,syy,sxy = %.3f,%.3f,%.3f, "
                      "more than --max-law-error %.3g %%: not exported (--force writes it anyway)",
                      check == &law.cone_check ? "" : " after the fuse", law::checked_against_text(c.against),
                      100 * c.max_error, c.worst(0), c.worst(1), c.worst(2), 100 * options.max_law_error);
        throw InputError(options.law_file.string() + ": " + text_);
      }
      text = io::law_umat(law, options.name, options.law_file.string());
      break;
    }
  }
  io::write_output(options.out, text);
  return describe(law, options.format, options.name);
}

void print_fit_summary(const std::filesystem::path& sweep_file, const std::filesystem::path& out, const law::Law& law) {
  std::printf("dualcell-fit: %s -> %s (%zu directions)\n", sweep_file.c_str(), out.c_str(), law.directions.size());
  std::printf("  %8s %12s %10s %12s %10s %8s %8s %8s %12s %10s\n", "theta", "E_tension", "se", "E_compress", "se",
              "Ec/Et", "nu_t", "nu_c", "fuse_stress", "jump x");
  for (const auto& d : law.directions)
    std::printf("  %8.2f %12.5g %10.2e %12.5g %10.2e %8.4f %8.4f %8.4f %12.5g %10.3g\n", d.direction_deg, d.E_tension,
                d.E_tension_se, d.E_compression, d.E_compression_se, d.E_compression / d.E_tension, d.nu_tension,
                d.nu_compression, d.fuse_stress, d.fuse_strain_ratio);
  for (const auto* fit : {&law.tension, &law.compression}) {
    std::printf("  S_%s (engineering shear), rank %d, relative residual %.2e, %s:\n",
                fit == &law.tension ? "tension" : "compression", fit->rank, fit->relative_residual,
                fit->rank < 6 ? "not all entries determined by these directions"
                              : (fit->symmetric_positive_definite ? "SPD" : "NOT positive definite"));
    for (int i = 0; i < 3; ++i) std::printf("    %14.6e %14.6e %14.6e\n", fit->S(i, 0), fit->S(i, 1), fit->S(i, 2));
  }
  if (!std::isnan(law.cone_rank_one_ratio))
    std::printf("  cone-wise linear (Curnier-He-Zysset): rank-one ratio %.3f -> %s\n", law.cone_rank_one_ratio,
                law.cone_wise_linear ? "yes" : "no (the stiffness jump is not rank-one)");
  for (const auto* cone : {&law.cone, &law.cone_after_fuse}) {
    const char* name = cone == &law.cone ? "cone-wise law" : "cone-wise law after the fuse";
    if (!cone->ok) {
      std::printf("  %s: none (%s)\n", name, cone->message.c_str());
      continue;
    }
    std::printf("  %s: %s, %zu planes, relative residual %.3g over %d points (one plane %.3g, struts %.3g)\n", name,
                cone->form.c_str(), cone->law.q.size(), cone->relative_residual, cone->n_points,
                cone->one_plane_residual, cone->struts_residual);
    std::printf("    %8s %12s %12s\n", "theta", "E_tension", "E_compress");
    for (const auto& d : law.directions)
      std::printf("    %8.2f %12.5g %12.5g\n", d.direction_deg, law::apparent_modulus(cone->law, d.direction_deg, 1),
                  law::apparent_modulus(cone->law, d.direction_deg, -1));
  }
  if (law.onset.linear) {
    const law::OnsetCheck check = law::check_against_sweep(law.onset);
    std::printf("  onset surface: %ld facets; predicts the onset of %d swept paths to %.2e relative\n",
                static_cast<long>(law.onset.facets.rows()), check.paths, check.worst_relative);
  } else {
    std::printf("  onset surface: none (%s)\n", law.onset.message.c_str());
  }
  if (law.cell) {
    const law::CellReplay& c = law.cell_replay;
    std::printf(
        "  exact law: the cell on %d interface rows; replays the sweep's %d points to max %.2e, rms %.2e "
        "(limit %.1e), broken bonds %s\n",
        law.cell->n_rows(), c.points, c.max_error, c.rms_error, c.limit,
        c.break_mismatches == 0 ? "the same at every point"
                                : (std::to_string(c.break_mismatches) + " points differ").c_str());
  } else {
    std::printf("  exact law: none (%s)\n", law.cell_note.c_str());
  }
  for (const auto* check : {&law.cone_check, &law.cone_after_fuse_check}) {
    if (check->directions.empty()) continue;
    const law::ConeCheck& c = *check;
    const bool exact = c.against == law::CheckedAgainst::exact_law;
    std::printf(
        "  cone-wise law%s against %s%s at %zu %s: stress error max %.1f %% (at sxx,syy,sxy = %.3f,%.3f,%.3f), "
        "rms %.1f %%\n",
        check == &law.cone_check ? "" : " after the fuse", law::checked_against_text(c.against),
        check == &law.cone_check || !exact ? "" : " at twice its onset", c.directions.size(),
        exact ? "stress directions" : "points, each fitted without its direction", 100 * c.max_error, c.worst(0),
        c.worst(1), c.worst(2), 100 * c.rms_error);
  }
}

namespace {

// One unit of material under the compact law: the bonded cone-wise law until the stress leaves
// the onset surface, the law past the fuse from then on (the umat's rule).
struct ConeResponse {
  Eigen::Vector3d stress, strain;
  Eigen::Matrix3d tangent;
};
ConeResponse cone_at(const law::Law& law, const Eigen::Vector3d& value, bool strain_driven, bool& fused) {
  const bool can_fuse = law.cone_after_fuse.ok && law.onset.linear;
  const auto respond = [&](const law::ConeLaw& cone) {
    ConeResponse r;
    r.strain = strain_driven ? value : law::strain_for(cone, value);
    const law::ConeState state = law::evaluate(cone, r.strain);
    r.stress = strain_driven ? state.stress : value;
    r.tangent = state.tangent;
    return r;
  };
  ConeResponse r = respond(fused ? law.cone_after_fuse.law : law.cone.law);
  if (!fused && can_fuse && law::onset_measure(law.onset, r.stress) >= 1) {
    fused = true;
    r = respond(law.cone_after_fuse.law);
  }
  return r;
}

}  // namespace

LawPointsSummary evaluate_law(const LawPointsOptions& options) {
  io::check_outputs({options.out}, {options.law_file, options.points_file});
  const law::Law law = io::read_law(options.law_file);
  const io::LawPoints points = io::read_points_csv(options.points_file);
  const bool cell_form = options.form == LawForm::cell;
  if (cell_form && !law.cell)
    throw InputError(options.law_file.string() + ": has no exact law (" + law.cell_note +
                     "): use --form cone for the compact one");
  if (!cell_form && !law.cone.ok)
    throw InputError(options.law_file.string() + ": has no cone-wise law (" + law.cone.message + ")");

  std::string out = points.has_path ? "path," : "";
  out += options.strain_driven ? "sxx,syy,sxy" : "exx,eyy,gxy";
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j) {
      out.append(",C");
      out.push_back(static_cast<char>('0' + i));
      out.push_back(static_cast<char>('0' + j));
    }
  out += cell_form ? ",broken_pairs\n" : ",fused\n";

  LawPointsSummary summary;
  std::optional<law::CellEvaluator> evaluator;
  if (cell_form) evaluator.emplace(*law.cell);
  std::map<std::string, law::CellHistory> histories;
  std::map<std::string, bool> fused_paths;
  double seconds = 0;
  for (std::size_t i = 0; i < points.value.size(); ++i) {
    const Eigen::Vector3d& v = points.value[i];
    Eigen::Vector3d other;
    Eigen::Matrix3d tangent;
    long broken = 0;
    const auto t0 = std::chrono::steady_clock::now();
    if (cell_form) {
      law::CellHistory fresh;
      law::CellHistory& h = points.has_path ? histories.try_emplace(points.path[i], evaluator->unloaded()).first->second
                                            : (fresh = evaluator->unloaded());
      const law::CellResponse r = options.strain_driven ? evaluator->at_strain(v, h) : evaluator->at_stress(v, h);
      if (!r.ok)
        throw InputError(options.points_file.string() + ":" + std::to_string(points.line[i]) + ": " + r.message);
      other = options.strain_driven ? r.stress : r.strain;
      tangent = r.tangent;
      broken = r.broken;
      summary.qp_iterations += r.iterations;
      summary.qp_factorisations += r.factorisations;
    } else {
      bool fresh = false;
      bool& fused = points.has_path ? fused_paths[points.path[i]] : fresh;
      const ConeResponse r = cone_at(law, v, options.strain_driven, fused);
      other = options.strain_driven ? r.stress : r.strain;
      tangent = r.tangent;
      broken = fused ? 1 : 0;
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // Appended piece by piece (GCC 12 warns falsely on chains of string concatenation).
    if (points.has_path) out.append(points.path[i]).push_back(',');
    for (int k = 0; k < 3; ++k) out.append(csv_number(other(k))).push_back(',');
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) out.append(csv_number(tangent(a, b))).push_back(',');
    out.append(std::to_string(broken)).push_back('\n');
  }
  summary.rows = static_cast<int>(points.value.size());
  summary.paths = points.has_path ? static_cast<int>(cell_form ? histories.size() : fused_paths.size()) : summary.rows;
  summary.seconds = seconds;
  io::write_output(options.out, out);
  return summary;
}

}  // namespace dualcell::stage
