#include "stage/fit.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/progress.hpp"
#include "core/text.hpp"
#include "fit/fit.hpp"
#include "io/atomic_output.hpp"
#include "io/law_file.hpp"
#include "io/points_csv.hpp"
#include "io/sweep_file.hpp"
#include "law/cell_text.hpp"

namespace dualcell::stage {

law::Law run_fit(const std::filesystem::path& sweep_file, const std::filesystem::path& out,
                 const fit::FitOptions& options, bool progress) {
  io::check_outputs({out}, {sweep_file});
  const io::SweepHeader header = io::read_sweep_header(sweep_file);
  if (header.delta_T != 0)
    throw InputError(sweep_file.string() + ": delta_T = " + shortest(header.delta_T) +
                     ": the fit does not carry a temperature change yet (its secants would take the cool-down's "
                     "strain for a load's); the paths, their onsets from the cool-down and the cool-down's breaks are "
                     "in the file");
  const std::vector<sweep::PathResult> paths = io::read_sweep(sweep_file);
  law::Law law = [&] {
    Progress line("dualcell-fit", progress);
    return fit::fit_law(paths, header, options, &line);
  }();
  // The exact law must give back the sweep it came from, and where it carries the strain along
  // the fibres the sweep's checks of it; one that does not is not written.
  const auto refuse = [&](const law::CellReplay& c, const std::string& where, const char* why) {
    throw InputError(sweep_file.string() + ": the exact law misses the sweep's " + where + " by " +
                     formatted("%.3g", c.max_error) + " relative, more than " + formatted("%.3g", c.limit) +
                     " (1e3 × the sweep's QP tolerance" + why);
  };
  if (law.cell && !law.cell_replay.ok())
    refuse(law.cell_replay,
           "point (path " + std::to_string(law.cell_replay.worst_path) + ", step " +
               std::to_string(law.cell_replay.worst_step) + ")",
           "): the condensation is wrong for this cell");
  if (law.cell && law.cell->longitudinal == 1 && law.cell_longitudinal_replay.points == 0)
    throw InputError(sweep_file.string() +
                     ": the exact law carries the strain along the fibres, but the sweep has no converged check of it "
                     "(/longitudinal_check): not kept unchecked");
  if (law.cell && law.cell->longitudinal == 1 && !law.cell_longitudinal_replay.ok())
    refuse(law.cell_longitudinal_replay,
           "check " + std::to_string(law.cell_longitudinal_replay.worst_path) + " of the strain along the fibres",
           ("; " + std::to_string(law.cell_longitudinal_replay.points) + " checks)").c_str());
  if (law.cell && law.cell->shear == 2 && law.cell_shear_replay.points == 0)
    throw InputError(sweep_file.string() +
                     ": the exact law carries the shears along the fibres, but the sweep has no check of them "
                     "(/shear_check): not kept unchecked");
  if (law.cell && law.cell->shear == 2 && law.cell_shear_replay.break_mismatches > 0)
    throw InputError(sweep_file.string() +
                     ": the exact law's shear along the fibres breaks other pairs than the "
                     "sweep's one-body solve at " +
                     std::to_string(law.cell_shear_replay.break_mismatches) + " of its " +
                     std::to_string(law.cell_shear_replay.points) + " checks (/shear_check): not kept");
  if (law.cell && law.cell->shear == 2 && !law.cell_shear_replay.ok())
    refuse(law.cell_shear_replay,
           "check " + std::to_string(law.cell_shear_replay.worst_step) + " of the shear along the fibres",
           ("; " + std::to_string(law.cell_shear_replay.points) + " checks)").c_str());
  if (law.cell && law.cell->thermal == 1 && !law.cell_thermal_replay.ok())
    refuse(law.cell_thermal_replay, "bonded expansion (/expansion)",
           "): its temperature change is wrong for this cell");
  law.provenance.sweep_file = sweep_file.string();
  law.provenance.sweep_hash = file_hash(sweep_file);
  io::write_law(out, law);
  return law;
}

namespace {

// The exact law's lines of the summary: its replay of the sweep and, with ε33, of its checks.
void print_exact_law_summary(const law::Law& law) {
  if (law.cell) {
    const law::CellReplay& c = law.cell_replay;
    const bool sampled = law.cell->n_rows() > fit::max_checked_rows;
    std::printf(
        "  exact law: the cell on %d interface rows; replays %s %d points%s to max %.2e, rms %.2e "
        "(limit %.1e), broken bonds %s\n",
        law.cell->n_rows(), sampled ? "of the sweep" : "the sweep's", c.points,
        sampled ? (", every k-th path (at most " + std::to_string(fit::max_replayed_points) + " points above " +
                   std::to_string(fit::max_checked_rows) + " rows)")
                      .c_str()
                : "",
        c.max_error, c.rms_error, c.limit,
        c.break_mismatches == 0 ? "the same at every point"
                                : (std::to_string(c.break_mismatches) + " points differ").c_str());
    // The checks along the fibres: what the exact law meets, and how closely.
    const auto along = [](const char* what, const char* solves, const law::CellReplay& r) {
      std::printf(
          "  exact law along the fibres (%s): meets %d %s to max %.2e, rms %.2e (limit %.1e), broken pairs %s\n", what,
          r.points, solves, r.max_error, r.rms_error, r.limit,
          r.break_mismatches == 0 ? "the same at every check"
                                  : (std::to_string(r.break_mismatches) + " checks differ").c_str());
    };
    if (law.cell->longitudinal == 1)
      along("e33", "full solves of generalised plane strain", law.cell_longitudinal_replay);
    if (law.cell->shear == 2) along("shear", "one-body antiplane solves", law.cell_shear_replay);
    if (law.cell->thermal == 0 && law.ply.expansion.asked())
      std::printf(
          "  exact law with a temperature change: not kept (the sweep checks the delta_T column through the bonded "
          "ply's expansion, with adhesion and [load] macro = \"full\"%s)\n",
          law.ply.expansion.ok ? "" : (": " + law.ply.expansion.note).c_str());
    if (law.cell->thermal == 1)
      std::printf(
          "  exact law with a temperature change (its delta_T column): the bonded expansion meets the sweep's full "
          "solves (/expansion) to %.2e (limit %.1e)\n",
          law.cell_thermal_replay.max_error, law.cell_thermal_replay.limit);
    if (!law.ply.rows.empty()) {
      std::printf(
          "  the ply's constants from the exact law (axis 1 the fibres; /law/ply)%s:\n",
          law.ply.fuse_stress > 0
              ? (", after the fuse: the bonds sxx = " + formatted("%.4g", law.ply.fuse_stress) + " left").c_str()
              : "");
      std::printf("    %-10s %-11s %6s %9s %9s %9s %8s %8s %8s %9s %9s %9s\n", "state", "load", "broken", "E1", "E2",
                  "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23");
      for (const law::PlyConstants& r : law.ply.rows)
        std::printf("    %-10s %-11s %6d %9.5g %9.5g %9.5g %8.5g %8.5g %8.5g %9.5g %9.5g %9.5g\n", to_string(r.state),
                    r.sign > 0 ? "tension" : "compression", r.broken, r.E1, r.E2, r.E3, r.nu12, r.nu13, r.nu23, r.G12,
                    r.G13, r.G23);
    }
    if (!law.ply.note.empty() && law.cell->longitudinal == 1 && law.cell->shear == 2)
      std::printf("  the ply's constants: %s\n", law.ply.note.c_str());
  } else {
    std::printf("  exact law: none (%s)\n", law.cell_note.c_str());
  }
}

// The small cell's line: how it was fitted and its check.
void print_small_cell_summary(const law::Law& law) {
  if (law.small && law.small_check.against == law::CheckedAgainst::exact_law_past_fuse) {
    const law::SmallCellFit& s = law.small_fit;
    const law::ConeCheck& c = law.small_check;
    std::printf(
        "  small cell with a fuse: bonded, the exact bonded law and onset (%d facet rows); past the fuse %d rows "
        "fitted "
        "to the exact law's cascade paths along %d directions (3 points each) in %.1f s (max %.1f %%, rms %.1f %%); "
        "against %s along %zu other directions' paths (%d points each): max %.1f %% (at sxx,syy,sxy = "
        "%.3f,%.3f,%.3f), rms %.1f %%, %s the tolerance %.1f %%\n",
        law.small->n_rows() - s.rows, s.rows, s.training_directions, s.seconds, 100 * s.training_max_error,
        100 * s.training_rms_error, law::checked_against_text(c.against), c.directions.size(), law::past_fuse_steps + 1,
        100 * c.max_error, c.worst(0), c.worst(1), c.worst(2), 100 * c.rms_error,
        c.max_error <= s.tolerance ? "within" : "OVER", 100 * s.tolerance);
  } else if (law.small) {
    const law::SmallCellFit& s = law.small_fit;
    const law::ConeCheck& c = law.small_check;
    const bool exact = c.against == law::CheckedAgainst::exact_law;
    std::printf(
        "  small cell: %d rows fitted to %s at %d directions in %.1f s (max %.1f %%, rms %.1f %%); "
        "against %s at %zu other directions: max %.1f %% (at sxx,syy,sxy = %.3f,%.3f,%.3f), rms %.1f %%, "
        "%s the tolerance %.1f %%\n",
        s.rows, exact ? "the exact law" : "full solves", s.training_directions, s.seconds, 100 * s.training_max_error,
        100 * s.training_rms_error, law::checked_against_text(c.against), c.directions.size(), 100 * c.max_error,
        c.worst(0), c.worst(1), c.worst(2), 100 * c.rms_error, c.max_error <= s.tolerance ? "within" : "OVER",
        100 * s.tolerance);
  } else {
    std::printf("  small cell: none (%s)\n", law.small_note.c_str());
  }
  const law::PlyCheck& p = law.small_ply_check;
  if (law.small && p.directions > 0)
    std::printf(
        "  small cell of the whole ply: along the fibres fitted to %d points of the exact law (max %.1f %%, rms "
        "%.1f %%); against the exact law along %d other six-component strain paths (%d points): max %.1f %%, "
        "rms %.1f %%, below the onset %.1e, %s the tolerance %.1f %%\n",
        p.training_points, 100 * p.training_max_error, 100 * p.training_rms_error, p.directions, p.points,
        100 * p.max_error, 100 * p.rms_error, p.bonded_max_error,
        p.max_error <= law.small_fit.tolerance ? "within" : "OVER", 100 * law.small_fit.tolerance);
}

}  // namespace

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
  const law::PlyExpansion& a = law.ply.expansion;
  if (a.ok)
    std::printf(
        "  bonded ply's thermal expansion per K (axis 1 the fibres; /law/expansion): alpha1 %.5g  alpha2 %.5g  "
        "alpha3 %.5g  alpha23 %.3g\n",
        a.alpha1, a.alpha2, a.alpha3, a.alpha23);
  else if (!a.note.empty())
    std::printf("  bonded ply's thermal expansion: none (%s)\n", a.note.c_str());
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
  print_exact_law_summary(law);
  print_small_cell_summary(law);
  for (const auto* check : {&law.cone_check, &law.cone_after_fuse_check}) {
    if (check->directions.empty()) continue;
    const law::ConeCheck& c = *check;
    const bool exact = c.against == law::CheckedAgainst::exact_law;
    std::printf(
        "  cone-wise law%s against %s%s at %zu %s: stress error max %.1f %% (at sxx,syy,sxy = %.3f,%.3f,%.3f), "
        "rms %.1f %%\n",
        check == &law.cone_check ? "" : " after the fuse", law::checked_against_text(c.against),
        check == &law.cone_check || !exact ? "" : " at twice its onset", c.directions.size(),
        exact                                               ? "stress directions"
        : c.against == law::CheckedAgainst::held_out_solves ? "sphere paths fitted without them"
                                                            : "points, each fitted without its direction",
        100 * c.max_error, c.worst(0), c.worst(1), c.worst(2), 100 * c.rms_error);
  }
}

}  // namespace dualcell::stage
