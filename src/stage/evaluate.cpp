#include "stage/evaluate.hpp"

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

// values.csv's header: the path (with that column), the other quantity and the tangent by row;
// `n`: the components (3 in-plane, 4 with ε33, 6 the whole ply).
std::string header_line(bool has_path, bool strain_driven, bool cell_form, int n) {
  std::string out = has_path ? "path," : "";
  out += strain_driven ? "sxx,syy,sxy" : "exx,eyy,gxy";
  if (n >= 4) out += ",szz";
  if (n == 6) out += ",sxz,syz";
  const int square = n == 6 ? 6 : 3;
  for (int i = 1; i <= square; ++i)
    for (int j = 1; j <= square; ++j) {
      out.append(",C");
      out.push_back(static_cast<char>('0' + i));
      out.push_back(static_cast<char>('0' + j));
    }
  if (n == 4) out += ",C14,C24,C34,C44";
  out += cell_form ? ",broken_pairs\n" : ",fused\n";
  return out;
}

// One row's answer: the other quantity (3 in-plane, then σ33, τxz, τyz where asked) and the
// tangent's entries in the header's order.
struct RowValues {
  Eigen::Matrix<double, 6, 1> other = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<double> tangent;
  long broken = 0;
};

// The tangent entries of a cell's response for n components: the 3 × 3 by row, then (n = 4) the
// ε33 column with dσ33/dε33; or (n = 6) the 6 × 6 by row, in-plane and ε33 coupled, the shears
// along the fibres on their own (no stiffness couples them to the rest).
std::vector<double> tangent_entries(const law::CellResponse& r, int n) {
  std::vector<double> out;
  if (n == 6) {
    const Eigen::Matrix<double, 6, 6> D = law::ply_tangent(r);
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b) out.push_back(D(a, b));
    return out;
  }
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) out.push_back(r.tangent(a, b));
  if (n == 4) {
    for (int k = 0; k < 3; ++k) out.push_back(r.tangent_zz(k));
    out.push_back(r.tangent_zz_zz);
  }
  return out;
}

// One row of values.csv, appended piece by piece (GCC 12 warns falsely on chains of string
// concatenation).
void append_row(std::string& out, const std::string* path, const RowValues& v, int n) {
  if (path) out.append(*path).push_back(',');
  const int others = n == 6 ? 6 : n == 4 ? 4 : 3;
  for (int k = 0; k < others; ++k) out.append(csv_number(v.other(k))).push_back(',');
  for (const double t : v.tangent) out.append(csv_number(t)).push_back(',');
  out.append(std::to_string(v.broken)).push_back('\n');
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
  return cell;
}

}  // namespace

LawPointsSummary evaluate_law(const LawPointsOptions& options) {
  io::check_outputs({options.out}, {options.law_file, options.points_file});
  const law::Law law = io::read_law(options.law_file);
  if (options.full && options.eps33) throw InputError("--full has ε33 already: leave out --eps33");
  const int n = options.full ? 6 : options.eps33 ? 4 : 3;
  const law::LawForm form = law::pick_form(law, options.form, options.law_file.string());
  const law::CondensedCell* cell = chosen_cell(law, options, form);
  io::PointsReader points(options.points_file, n);
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
  // The stress (strain) and tangent entries a cell without shear leaves NaN (n_macro = 2).
  const int n_finite = cell_form ? cell->n_macro : 3;
  double seconds = 0;
  io::LawPoint point;
  while (points.next(point)) {
    // After the first row: whether the file has the path column is known then.
    if (summary.rows == 0) out = header_line(points.has_path(), options.strain_driven, cell_form, n);
    const auto where = [&] { return options.points_file.string() + ":" + std::to_string(point.line) + ": "; };
    // The row's state: its in-plane part a stress where the points are stresses.
    if (!options.strain_driven) point.state.stress_driven = MacroState::in_plane_mask;
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
      law::CellHistory& h = points.has_path() ? histories.try_emplace(point.path, evaluator->unloaded()).first->second
                                              : (fresh = evaluator->unloaded());
      const law::CellResponse r = evaluator->at(point.state, h);
      if (!r.ok) throw InputError(where() + r.message);
      row.other = law::ply_stress(r);
      if (!options.strain_driven) row.other.head<3>() = r.strain;
      row.tangent = tangent_entries(r, n);
      row.broken = r.broken;
      summary.qp_iterations += r.iterations;
      summary.qp_factorisations += r.factorisations;
      summary.qp_updates += r.updates;
    } else {
      bool fresh = false;
      bool& fused = points.has_path() ? fused_paths[point.path] : fresh;
      const ConeResponse r = cone_at(law, v, options.strain_driven, fused);
      row.other.head<3>() = options.strain_driven ? r.stress : r.strain;
      row.tangent.assign(r.tangent.data(), r.tangent.data() + 9);  // symmetric: by row as by column
      row.broken = fused ? 1 : 0;
    }
    seconds += seconds_since(t0);
    // No NaN or Inf leaves with exit 0: an input this large overflows the law's answer. A cell
    // without shear (n_macro = 2) leaves its shear entries NaN.
    // With ε33 stress-driven the tangent's ε33 entries are NaN by definition (not checked).
    bool finite = row.other.head(n_finite).allFinite() && (n == 3 || row.other.segment(3, n - 3).allFinite());
    const int square = n == 6 ? 6 : 3;
    for (int a = 0; a < square; ++a)
      for (int b = 0; b < square; ++b)
        if ((a < n_finite || a >= 3) && (b < n_finite || b >= 3))
          finite = finite && std::isfinite(row.tangent[static_cast<std::size_t>(square * a + b)]);
    if (!finite)
      throw InputError(
          where() + "the law's answer at (" + shortest(v(0)) + ", " + shortest(v(1)) + ", " + shortest(v(2)) + ")" +
          (point.state.eps33() != 0 ? ", eps33 " + shortest(point.state.eps33()) : "") +
          (point.state.gamma().isZero(0)
               ? ""
               : ", gamma (" + shortest(point.state.gamma()(0)) + ", " + shortest(point.state.gamma()(1)) + ")") +
          " is not finite (the input is beyond what the law carries in doubles)");
    ++summary.rows;
    append_row(out, points.has_path() ? &point.path : nullptr, row, n);
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
