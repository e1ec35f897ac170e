#pragma once
// The effective law of a cell block: what leaves the project (law.h5, layout in docs/reference/law-h5.md).
//
// Conventions: plane strain in the x–y plane, z = fibre direction. Stresses and moduli in the
// units of the input scene. In-plane compliances use engineering shear:
//   (εxx, εyy, γxy) = S (σxx, σyy, σxy),   γxy = 2 εxy,
// so S is symmetric for an elastic law. Per direction θ (uniaxial stress s·n⊗n, n = (cos θ,
// sin θ), t = (−sin θ, cos θ)): ε_nn = n·ε·n, ε_tt = t·ε·t; the apparent plane-strain modulus
// is E = s/ε_nn and ν = −ε_tt/ε_nn. NaN marks a value the data do not determine.
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/fields.hpp"
#include "core/provenance.hpp"
#include "core/scene.hpp"
#include "law/condensed.hpp"
#include "law/cone.hpp"
#include "law/cone_check.hpp"
#include "law/onset.hpp"
#include "law/ply.hpp"
#include "law/ply_sample.hpp"

namespace dualcell::law {

struct DirectionLaw {
  double direction_deg = 0;
  // Least squares through the origin on the points before any bond breaks (GSL gsl_fit_mul).
  double E_tension = 0, E_tension_se = 0, E_tension_r2 = 0;
  double E_compression = 0, E_compression_se = 0, E_compression_r2 = 0;
  int n_tension = 0, n_compression = 0;  // points used
  double nu_tension = 0, nu_tension_se = 0;
  double nu_compression = 0, nu_compression_se = 0;
  // Adhesion (NaN where no bond breaks along the tension path of this direction):
  double onset_stress = 0;       // s*: the first bond reaches its strength
  double fuse_stress = 0;        // the largest load that holds before the largest jump (fuse/load_before)
  double fuse_stress_after = 0;  // the smallest load past it (fuse/load_after)
  double fuse_strain_jump = 0;   // ε_nn after − before the jump
  double fuse_strain_ratio = 0;  // ε_nn after / before
  double E_after_fuse = 0, E_after_fuse_se = 0;  // tangent modulus past the jump (GSL gsl_fit_linear)
};

// A 3×3 compliance fitted to all directions at once, with its quality.
struct ComplianceFit {
  Eigen::Matrix3d S = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Matrix3d S_se = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  int rank = 0;                            // of the least-squares design (6 unknowns of the symmetric S)
  double relative_residual = 0;            // ‖ε − Sσ‖ / ‖ε‖ over all points used
  std::vector<double> direction_residual;  // the same per direction (same order as directions)
  bool symmetric_positive_definite = false;
  int n_points = 0;
};

// The exact law replayed through every converged point of the sweep it came from (above
// fit::max_checked_rows rows through those of every k-th path, fit::replay_stride): the strain it
// gives for the point's stress (the bonds carried along the path) against the sweep's strain.
struct CellReplay {
  int points = 0;
  double max_error = std::numeric_limits<double>::quiet_NaN();  // max ‖ε_law − ε_sweep‖ / ‖ε_sweep‖
  double rms_error = std::numeric_limits<double>::quiet_NaN();
  int worst_path = -1, worst_step = -1;
  int break_mismatches = 0;  // points where the law's count of broken bonds differs from the sweep's
  // What the error may reach: the sweep's QP stopped at a relative tolerance t, which reaches the
  // strain amplified by the conditioning of the dual problem (≲ 1e2 measured): 1e3·t.
  double limit = std::numeric_limits<double>::quiet_NaN();
  bool ok() const { return points > 0 && max_error <= limit; }
};
// Its members, listed once (core/fields.hpp): law.h5's /law/cell_replay (written, and read
// with counts checked to be at least min_count) and the JSON walk it.
inline constexpr Field<CellReplay, int, double> cell_replay_fields[] = {
    {"points", &CellReplay::points},
    {"max_error", &CellReplay::max_error},
    {"rms_error", &CellReplay::rms_error},
    {"worst_path", &CellReplay::worst_path, -1},
    {"worst_step", &CellReplay::worst_step, -1},
    {"break_mismatches", &CellReplay::break_mismatches},
    {"limit", &CellReplay::limit},
};

// How the small cell was fitted: the tolerance asked for (the largest stress error over the
// sphere), the rows m, its largest and rms error over the fit's own directions, and the cost.
struct SmallCellFit {
  double tolerance = std::numeric_limits<double>::quiet_NaN();
  int rows = 0;
  int training_directions = 0;
  double training_max_error = std::numeric_limits<double>::quiet_NaN();
  double training_rms_error = std::numeric_limits<double>::quiet_NaN();
  int iterations = 0;
  double seconds = 0;
};

// Its members, listed once (core/fields.hpp): /law/small_fit in law.h5 and the JSON.
inline constexpr Field<SmallCellFit, double, int> small_cell_fit_fields[] = {
    {"tolerance", &SmallCellFit::tolerance},
    {"rows", &SmallCellFit::rows},
    {"training_directions", &SmallCellFit::training_directions},
    {"training_max_error", &SmallCellFit::training_max_error},
    {"training_rms_error", &SmallCellFit::training_rms_error},
    {"iterations", &SmallCellFit::iterations},
    {"seconds", &SmallCellFit::seconds},
};

struct Law {
  std::vector<DirectionLaw> directions;  // ascending direction_deg
  ComplianceFit tension, compression;
  // Cone-wise linear form (docs/method.md §14): the stiffness jump
  // C_t − C_c across the switching plane must be rank-one, ΔC = β q⊗q.
  double cone_rank_one_ratio = 0;                         // |second eigenvalue| / |first| of ΔC (0 = exactly rank-one)
  bool cone_wise_linear = false;                          // ratio below 0.05 and both fits SPD
  Eigen::Vector3d cone_normal = Eigen::Vector3d::Zero();  // q (unit), in engineering-shear strain space
  double cone_beta = 0;                                   // β
  // The cone-wise law fitted to every point before any break (an admissible law for every
  // strain, law/cone.hpp), and to the points past the largest jump of each path that has one
  // (the debonded cell a structure switches to, irreversibly).
  ConeFit cone, cone_after_fuse;
  // Where the bonded law ends: the exact debond onset surface of the cell (with adhesion), and
  // its prediction checked against every sweep path.
  OnsetSurface onset;
  // The exact law: the cell condensed onto its interface rows (law/condensed.hpp), as the sweep
  // built it; none where the scene has none (cell_note says why). cell_replay is its check
  // against every converged point of that sweep, replayed along each path with its history.
  std::optional<CondensedCell> cell;
  std::string cell_note;
  CellReplay cell_replay;
  // Where the cell carries the strain along the fibres: its replay of the sweep's checks of it,
  // full solves of generalised plane strain (sweep::LongitudinalPoint; worst_path is the point's
  // index, worst_step −1). Empty (0 points) otherwise.
  CellReplay cell_longitudinal_replay;
  // Where the cell carries the shears along the fibres: its replay of the sweep's one-body checks
  // of them (sweep::ShearPoint). Empty (0 points) otherwise.
  CellReplay cell_shear_replay;
  // Where the cell carries a temperature change (and the strain along the fibres): the bonded
  // ply's expansion from the exact law (its ΔT column, bonds lifted) against the sweep's full
  // solves of it (/expansion); one point, the relative error of (α2, α3, α23, α1). Empty
  // otherwise.
  CellReplay cell_thermal_replay;
  // Where the cell carries the whole ply (the strain and the shears along the fibres): its nine
  // engineering constants per bond state and sign, from the exact law (law/ply.hpp); empty
  // otherwise (ply.note says why).
  PlyTable ply;
  // The compact law (cone) against the exact one over a dense set of directions, or without an
  // exact law against the sweep's points, each direction held out of the fit in turn
  // (ConeCheck::against); empty without a cone-wise law, or without an exact law and with one
  // sweep direction only.
  ConeCheck cone_check;
  // The compact law past the fuse (cone_after_fuse) against the exact law past the fuse: the
  // same directions, each loaded from the intact cell to twice its onset along the path
  // (sample_cell_past_fuse); without an exact law against held-out directions as above; empty
  // without adhesion or a law past the fuse.
  ConeCheck cone_after_fuse_check;
  // The compact law as a small cell (fit/small_cell.hpp, docs/method.md §16c): the exact law's
  // form with m rows fitted to it, evaluated by the exact law's evaluator; none where the fit
  // made none (small_note says why). small_check measures it against the exact law on the
  // check's directions (as cone_check), none of them among the fit's.
  std::optional<CondensedCell> small;
  std::string small_note;
  SmallCellFit small_fit;
  ConeCheck small_check;
  // Where the small cell carries the whole ply (the exact law does: the strain and the shears
  // along the fibres, docs/method.md §16e): its fit along the fibres and its check along strain
  // paths of all six components (law/ply_sample.hpp); 0 directions otherwise.
  PlyCheck small_ply_check;
  // Constituents, for the out-of-plane constants of the exports (rule of mixtures).
  Constituents constituents;
  std::string units = "stress and moduli in the units of the input scene; strains dimensionless";
  std::string stress_state = "plane strain";
  // The sweep's provenance, with the sweep file and its hash, and the fit's code version.
  Provenance provenance;
};

// The exact law's replays, as law.h5 (/law/<name>/…) and the JSON name them: of the sweep's
// paths, of its checks of the strain along the fibres, of its checks of the shears along them.
struct CellReplayMember {
  const char* name;
  CellReplay Law::*replay;
};
inline constexpr CellReplayMember cell_replay_members[] = {
    {"cell_replay", &Law::cell_replay},
    {"cell_longitudinal_replay", &Law::cell_longitudinal_replay},
    {"cell_shear_replay", &Law::cell_shear_replay},
    {"cell_thermal_replay", &Law::cell_thermal_replay},
};
// Whether the cell carries what replay m checks (the in-plane replay always; the others with
// their part of the cell: longitudinal, shear).
inline bool carries(const CondensedCell& cell, const CellReplayMember& m) {
  if (m.replay == &Law::cell_longitudinal_replay) return cell.longitudinal == 1;
  if (m.replay == &Law::cell_shear_replay) return cell.shear == 2;
  if (m.replay == &Law::cell_thermal_replay) return cell.thermal == 1;
  return true;
}

}  // namespace dualcell::law
