#include "stage/evaluate.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
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

// values.csv's header: the path (with that column), the other quantity and the tangent by row.
std::string header_line(bool has_path, bool strain_driven, bool cell_form, bool eps33) {
  std::string out = has_path ? "path," : "";
  out += strain_driven ? "sxx,syy,sxy" : "exx,eyy,gxy";
  if (eps33) out += ",szz";
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j) {
      out.append(",C");
      out.push_back(static_cast<char>('0' + i));
      out.push_back(static_cast<char>('0' + j));
    }
  if (eps33) out += ",C14,C24,C34,C44";
  out += cell_form ? ",broken_pairs\n" : ",fused\n";
  return out;
}

// With ε33: σ33 and the tangent's ε33 column (dσ̄/dε33, dσ33/dε33).
struct AlongFibres {
  double stress_zz = 0;
  Eigen::Vector4d tangent = Eigen::Vector4d::Zero();
};

// One row of values.csv, appended piece by piece (GCC 12 warns falsely on chains of string
// concatenation).
void append_row(std::string& out, const std::string* path, const Eigen::Vector3d& other, const Eigen::Matrix3d& tangent,
                long broken, const AlongFibres* fibres) {
  if (path) out.append(*path).push_back(',');
  for (int k = 0; k < 3; ++k) out.append(csv_number(other(k))).push_back(',');
  if (fibres) out.append(csv_number(fibres->stress_zz)).push_back(',');
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) out.append(csv_number(tangent(a, b))).push_back(',');
  if (fibres)
    for (int k = 0; k < 4; ++k) out.append(csv_number(fibres->tangent(k))).push_back(',');
  out.append(std::to_string(broken)).push_back('\n');
}

// The histories of the paths held at once (one per path value seen): at most this many bytes.
constexpr std::size_t max_history_bytes = std::size_t{1} << 30;
// Output is appended in pieces of about this size, so it is never held whole.
constexpr std::size_t output_piece = std::size_t{1} << 20;

// The cell the form evaluates (the exact law or its small cell, evaluated alike), or nullptr for
// the cone-wise law; an InputError naming the file where the law has no such form, or no ε33 for
// --eps33.
const law::CondensedCell* chosen_cell(const law::Law& law, const LawPointsOptions& options) {
  if (options.form == LawForm::cell && !law.cell)
    throw InputError(options.law_file.string() + ": has no exact law (" + law.cell_note +
                     "): use --form cone for the compact one");
  if (options.form == LawForm::small && !law.small)
    throw InputError(options.law_file.string() + ": has no small cell (" + law.small_note +
                     "): use --form cell or cone");
  const law::CondensedCell* cell = options.form == LawForm::cell    ? &*law.cell
                                   : options.form == LawForm::small ? &*law.small
                                                                    : nullptr;
  const bool cell_form = cell != nullptr;
  if (options.eps33 && (!cell_form || cell->longitudinal == 0))
    throw InputError(options.law_file.string() + ": --eps33: " +
                     (cell_form
                          ? std::string("its cell has no strain along the fibres (fit a scene with [load] macro = "
                                        "\"full\"; the small cell has none yet)")
                          : std::string("the cone-wise law has no strain along the fibres (use --form cell)")));
  if (!cell_form && !law.cone.ok)
    throw InputError(options.law_file.string() + ": has no cone-wise law" +
                     (law.cone.message.empty() ? std::string() : " (" + law.cone.message + ")"));

  return cell;
}

}  // namespace

LawPointsSummary evaluate_law(const LawPointsOptions& options) {
  io::check_outputs({options.out}, {options.law_file, options.points_file});
  const law::Law law = io::read_law(options.law_file);
  io::PointsReader points(options.points_file, options.eps33 ? 4 : 3);
  const law::CondensedCell* cell = chosen_cell(law, options);
  const bool cell_form = cell != nullptr;

  io::AtomicOutputs outputs;
  outputs.add(options.out);
  std::string out;
  out.reserve(output_piece + 4096);

  LawPointsSummary summary;
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
    if (summary.rows == 0) out = header_line(points.has_path(), options.strain_driven, cell_form, options.eps33);
    const auto where = [&] { return options.points_file.string() + ":" + std::to_string(point.line) + ": "; };
    const Eigen::Vector3d& v = point.value;
    if (points.has_path() && !(cell_form ? histories.count(point.path) : fused_paths.count(point.path))) {
      held_bytes += history_bytes + point.path.size();
      if (held_bytes > max_history_bytes)
        throw InputError(where() + "path '" + clipped(point.path) + "' is the " +
                         std::to_string((cell_form ? histories.size() : fused_paths.size()) + 1) +
                         "th path held at once; their histories would pass the 1 GiB dualcell-law keeps (split the "
                         "file by path)");
    }
    Eigen::Vector3d other;
    Eigen::Matrix3d tangent;
    AlongFibres fibres;
    long broken = 0;
    const auto t0 = std::chrono::steady_clock::now();
    if (cell_form) {
      law::CellHistory fresh;
      law::CellHistory& h = points.has_path() ? histories.try_emplace(point.path, evaluator->unloaded()).first->second
                                              : (fresh = evaluator->unloaded());
      const law::CellResponse r = options.strain_driven
                                      ? evaluator->at_strain(v, h, law::BondMode::cascade, point.eps33)
                                      : evaluator->at_stress(v, h, point.eps33);
      if (!r.ok) throw InputError(where() + r.message);
      other = options.strain_driven ? r.stress : r.strain;
      tangent = r.tangent;
      fibres.stress_zz = r.stress_zz;
      fibres.tangent << r.tangent_zz, r.tangent_zz_zz;
      broken = r.broken;
      summary.qp_iterations += r.iterations;
      summary.qp_factorisations += r.factorisations;
      summary.qp_updates += r.updates;
    } else {
      bool fresh = false;
      bool& fused = points.has_path() ? fused_paths[point.path] : fresh;
      const ConeResponse r = cone_at(law, v, options.strain_driven, fused);
      other = options.strain_driven ? r.stress : r.strain;
      tangent = r.tangent;
      broken = fused ? 1 : 0;
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // No NaN or Inf leaves with exit 0: an input this large overflows the law's answer.
    if (!other.head(n_finite).allFinite() || !tangent.topLeftCorner(n_finite, n_finite).allFinite())
      throw InputError(where() + "the law's answer at (" + shortest(v(0)) + ", " + shortest(v(1)) + ", " +
                       shortest(v(2)) + ") is not finite (the input is beyond what the law carries in doubles)");
    ++summary.rows;
    if (options.eps33 && !std::isfinite(fibres.stress_zz))
      throw InputError(where() + "the law's σ33 is not finite (the input is beyond what the law carries in doubles)");
    append_row(out, points.has_path() ? &point.path : nullptr, other, tangent, broken,
               options.eps33 ? &fibres : nullptr);
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
