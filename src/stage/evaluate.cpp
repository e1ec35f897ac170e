#include "stage/evaluate.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
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
#include "law/form.hpp"

namespace dualcell::stage {

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

// The components a row carries, in the law's order (core/macro_state.hpp): the in-plane three,
// ε33 with --eps33, and the shears along the fibres too with --full.
std::vector<MacroState::Component> carried_components(MacroState::Mask carried) {
  std::vector<MacroState::Component> out;
  for (int k = 0; k < MacroState::count; ++k)
    if (carried >> k & 1) out.push_back(static_cast<MacroState::Component>(k));
  return out;
}

// values.csv's header: the path (with that column), the other quantity per component carried (the
// in-plane one the strain where the rows are stresses; σ33, τxz, τyz), the tangent over the
// components carried by row (C11, C12, …, numbered 1 … k in that order) and the bond column.
std::string header_line(bool has_path, bool strain_driven, bool cell_form,
                        const std::vector<MacroState::Component>& carried) {
  static constexpr const char* stress_names[] = {"sxx", "syy", "sxy", "szz", "sxz", "syz"};
  static constexpr const char* strain_names[] = {"exx", "eyy", "gxy"};
  std::string out = has_path ? "path" : "";
  for (const MacroState::Component k : carried) {
    if (!out.empty()) out.push_back(',');
    out.append(k < 3 && !strain_driven ? strain_names[k] : stress_names[k]);
  }
  const int square = static_cast<int>(carried.size());
  for (int i = 1; i <= square; ++i)
    for (int j = 1; j <= square; ++j) out.append(",C").append(std::to_string(i)).append(std::to_string(j));
  out += cell_form ? ",broken_pairs\n" : ",fused\n";
  return out;
}

// One row's answer in the law's order (core/macro_state.hpp): the other quantity (the in-plane
// one, then σ33, τxz, τyz) and the tangent (6 × 6, NaN where the form has no entry).
struct RowValues {
  Eigen::Matrix<double, 6, 1> other = Eigen::Matrix<double, 6, 1>::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Matrix<double, 6, 6> tangent = Eigen::Matrix<double, 6, 6>::Constant(std::numeric_limits<double>::quiet_NaN());
  long broken = 0;
};

// One row of values.csv over the components carried, appended piece by piece (GCC 12 warns
// falsely on chains of string concatenation).
void append_row(std::string& out, const std::string* path, const RowValues& v,
                const std::vector<MacroState::Component>& carried) {
  if (path) out.append(*path).push_back(',');
  for (const MacroState::Component k : carried) out.append(csv_number(v.other(k))).push_back(',');
  for (const MacroState::Component a : carried)
    for (const MacroState::Component b : carried) out.append(csv_number(v.tangent(a, b))).push_back(',');
  out.append(std::to_string(v.broken)).push_back('\n');
}

// Whether a row's answer is finite on the components that must be: the other quantity where
// `finite` has the component, the tangent's entries where `finite_tangent` has both.
bool answer_finite(const RowValues& row, const std::vector<MacroState::Component>& carried, MacroState::Mask finite,
                   MacroState::Mask finite_tangent) {
  for (const MacroState::Component a : carried) {
    if (!(finite >> a & 1)) continue;
    if (!std::isfinite(row.other(a))) return false;
    for (const MacroState::Component b : carried)
      if (finite_tangent >> a & 1 && finite_tangent >> b & 1 && !std::isfinite(row.tangent(a, b))) return false;
  }
  return true;
}

// "the law's answer at (…), eps33 …, gamma (…)": the row's state as a message names it.
std::string not_finite(const MacroState& state) {
  const Eigen::Vector3d v = state.in_plane();
  std::string out = "the law's answer at (";
  out.append(shortest(v(0))).append(", ").append(shortest(v(1))).append(", ").append(shortest(v(2))).append(")");
  if (state.eps33() != 0) out.append(", eps33 ").append(shortest(state.eps33()));
  if (state.delta_T() != 0) out.append(", delta_T ").append(shortest(state.delta_T()));
  if (!state.gamma().isZero(0))
    out.append(", gamma (")
        .append(shortest(state.gamma()(0)))
        .append(", ")
        .append(shortest(state.gamma()(1)))
        .append(")");
  return out;
}

// The histories of the paths held at once (one per path value seen): at most this many bytes.
constexpr std::size_t max_history_bytes = std::size_t{1} << 30;
// Output is appended in pieces of about this size, so it is never held whole.
constexpr std::size_t output_piece = std::size_t{1} << 20;

// The cell the form evaluates (the exact law or its small cell, evaluated alike), or nullptr for
// the cone-wise law; an InputError naming the file where it has no ε33 for --eps33 or no shears
// for --full.
const law::CondensedCell* chosen_cell(const law::Law& law, const LawPointsOptions& options, law::LawForm form) {
  const law::CondensedCell* cell = form == law::LawForm::cone ? nullptr : &law::cell_of(law, form);
  const bool cell_form = cell != nullptr;
  if (options.full && !options.strain_driven)
    throw InputError(
        options.points_file.string() +
        ": --full is strain-driven (a 3D element gives the strain): use --strain, or --stress with --eps33");
  if (options.full && (!cell_form || cell->shear == 0))
    throw InputError(options.law_file.string() + ": --full: " +
                     (cell_form
                          ? std::string("its cell has no shear along the fibres (fit a scene with [load] macro "
                                        "= \"full\" and boundary = \"periodic\")")
                          : std::string("the cone-wise law has no components along the fibres (use --form cell)")));
  if (options.eps33 && (!cell_form || cell->longitudinal == 0))
    throw InputError(options.law_file.string() + ": --eps33: " +
                     (cell_form
                          ? std::string("its cell has no strain along the fibres (fit a scene with [load] macro = "
                                        "\"full\" and boundary = \"periodic\" for a small cell)")
                          : std::string("the cone-wise law has no strain along the fibres (use --form cell)")));
  if (options.delta_T != 0 && (!cell_form || cell->thermal == 0))
    throw InputError(options.law_file.string() + ": --delta-T: " +
                     (cell_form ? std::string("its cell has no temperature change (the exact law keeps one where "
                                              "both phases have alpha and the fit could check it: adhesion and "
                                              "[load] macro = \"full\"; the small cell not yet)")
                                : std::string("the cone-wise law has no temperature change (use --form cell)")));
  return cell;
}

// A path (or a row without one) starts from the cooled cell: the cool-down at zero stress first,
// its breaks the history's first round (docs/theory/model.md §1a).
void cool_down(law::CellEvaluator& evaluator, double delta_T, law::CellHistory& h, const std::string& where) {
  const law::CellResponse cool =
      evaluator.at(MacroState::stress(Eigen::Vector3d::Zero()).hold(MacroState::dT, delta_T), h);
  if (!cool.ok) throw InputError(where + "the cool-down: " + cool.message);
}

}  // namespace

LawPointsSummary evaluate_law(const LawPointsOptions& options) {
  io::check_outputs({options.out}, {options.law_file, options.points_file});
  const law::Law law = io::read_law(options.law_file);
  if (options.full && options.eps33) throw InputError("--full has ε33 already: leave out --eps33");
  const MacroState::Mask carried_mask = MacroState::in_plane_mask |
                                        (options.full || options.eps33 ? MacroState::along_mask : 0) |
                                        (options.full ? MacroState::shear_mask : 0);
  const std::vector<MacroState::Component> carried = carried_components(carried_mask);
  const law::LawForm form = law::pick_form(law, options.form, options.law_file.string());
  const law::CondensedCell* cell = chosen_cell(law, options, form);
  io::PointsReader points(options.points_file, carried_mask);
  const bool cell_form = cell != nullptr;

  io::AtomicOutputs outputs;
  outputs.add(options.out);
  std::string out;
  out.reserve(output_piece + 4096);

  LawPointsSummary summary;
  summary.form = law::to_string(form);
  std::optional<law::CellEvaluator> evaluator;
  if (cell_form)
    evaluator.emplace(*cell, options.factorise_each ? qp::DenseActiveSet::Updates::factorise_each
                                                    : qp::DenseActiveSet::Updates::bordered);
  // What one path's history holds: its bond state, its active set and the map's node.
  const std::size_t history_bytes =
      cell_form ? static_cast<std::size_t>(cell->n_pairs + cell->n_macro + cell->n_rows()) + 128 : 64;
  std::size_t held_bytes = 0;
  std::map<std::string, law::CellHistory> histories;
  std::map<std::string, bool> fused_paths;
  // The components whose answer must be finite: a cell without shear (n_macro = 2) leaves γxy
  // and its tangent entries NaN.
  const MacroState::Mask finite_mask =
      carried_mask & static_cast<MacroState::Mask>(cell_form && cell->n_macro == 2 ? ~(1 << MacroState::xy) : ~0);
  // And the tangent's: with ε33 held and the in-plane part a stress, the ε33 entries are NaN by
  // definition.
  const MacroState::Mask finite_tangent_mask =
      finite_mask & static_cast<MacroState::Mask>(options.strain_driven ? ~0 : ~MacroState::along_mask);
  double seconds = 0;
  io::LawPoint point;
  while (points.next(point)) {
    // After the first row: whether the file has the path column is known then.
    if (summary.rows == 0) out = header_line(points.has_path(), options.strain_driven, cell_form, carried);
    const auto where = [&] { return options.points_file.string() + ":" + std::to_string(point.line) + ": "; };
    // The row's state: its in-plane part a stress where the points are stresses; the temperature
    // change held.
    if (!options.strain_driven) point.state.stress_driven = MacroState::in_plane_mask;
    if (options.delta_T != 0) point.state.hold(MacroState::dT, options.delta_T);
    const Eigen::Vector3d v = point.state.in_plane();
    if (points.has_path() && !(cell_form ? histories.count(point.path) : fused_paths.count(point.path))) {
      held_bytes += history_bytes + point.path.size();
      if (held_bytes > max_history_bytes)
        throw InputError(where() + "path '" + clipped(point.path) + "' is the " +
                         std::to_string((cell_form ? histories.size() : fused_paths.size()) + 1) +
                         "th path held at once; their histories would pass the 1 GiB dualcell-law keeps (split the "
                         "file by path)");
    }
    RowValues row;
    const auto t0 = std::chrono::steady_clock::now();
    if (cell_form) {
      law::CellHistory fresh;
      const auto [it, new_path] = points.has_path() ? histories.try_emplace(point.path, evaluator->unloaded())
                                                    : std::pair{histories.end(), true};
      law::CellHistory& h = points.has_path() ? it->second : (fresh = evaluator->unloaded());
      if (new_path && options.delta_T != 0) cool_down(*evaluator, options.delta_T, h, where());
      const law::CellResponse r = evaluator->at(point.state, h);
      if (!r.ok) throw InputError(where() + r.message);
      row.other = law::ply_stress(r);
      if (!options.strain_driven) row.other.head<3>() = r.strain;
      row.tangent = law::ply_tangent(r);
      row.broken = r.broken;
      summary.qp_iterations += r.iterations;
      summary.qp_factorisations += r.factorisations;
      summary.qp_updates += r.updates;
    } else {
      bool fresh = false;
      bool& fused = points.has_path() ? fused_paths[point.path] : fresh;
      const ConeResponse r = cone_at(law, v, options.strain_driven, fused);
      row.other.head<3>() = options.strain_driven ? r.stress : r.strain;
      row.tangent.topLeftCorner<3, 3>() = r.tangent;
      row.broken = fused ? 1 : 0;
    }
    seconds += seconds_since(t0);
    // No NaN or Inf leaves with exit 0: an input this large overflows the law's answer.
    if (!answer_finite(row, carried, finite_mask, finite_tangent_mask))
      throw InputError(where() + not_finite(point.state) +
                       " is not finite (the input is beyond what the law carries in doubles)");
    ++summary.rows;
    append_row(out, points.has_path() ? &point.path : nullptr, row, carried);
    if (out.size() >= output_piece) {
      outputs.append(options.out, out);
      out.clear();
    }
  }
  outputs.append(options.out, out);
  outputs.commit();
  summary.paths =
      points.has_path() ? static_cast<int>(cell_form ? histories.size() : fused_paths.size()) : summary.rows;
  summary.seconds = seconds;
  return summary;
}

}  // namespace dualcell::stage
