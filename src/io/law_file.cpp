#include "io/law_file.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/condensed_group.hpp"
#include "io/fields_io.hpp"
#include "io/file_root.hpp"
#include "io/hdf5.hpp"
#include "io/onset_group.hpp"
#include "law/fields.hpp"

namespace dualcell::io {

namespace {

using law::compliance_members;
using law::ComplianceFit;
using law::direction_columns;
using law::Law;
using law::ply_constant_fields;
using law::PlyConstants;
using law::PlyState;
using law::PlyTable;

const std::string group = "/law";

std::string object(const std::string& name) { return group + "/" + name; }

std::vector<double> row_major(const Eigen::Matrix3d& m) {
  std::vector<double> v;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v.push_back(m(i, j));
  return v;
}

void write_scalar(File& f, const std::string& name, double value) {
  f.write(object(name), std::vector<double>{value}, {1});
}

void write_count(File& f, const std::string& name, std::int64_t value) {
  f.write(object(name), std::vector<std::int64_t>{value}, {1});
}

void write_ply(File& f, const PlyTable& t) {
  f.create_group(object("ply"));
  std::vector<std::int64_t> state, sign, broken;
  std::vector<double> constants, left;
  for (const PlyConstants& c : t.rows) {
    state.push_back(static_cast<std::int64_t>(c.state));
    sign.push_back(c.sign);
    broken.push_back(c.broken);
    for_each_field(ply_constant_fields, c, [&](const auto&, double v) { constants.push_back(v); });
    left.push_back(c.sigma33_left);
  }
  const hsize_t n = t.rows.size();
  f.write(object("ply/state"), state, {n});
  f.write(object("ply/sign"), sign, {n});
  f.write(object("ply/broken"), broken, {n});
  f.write(object("ply/constants"), constants, {n, std::size(ply_constant_fields)});
  f.write(object("ply/sigma33_left"), left, {n});
  write_scalar(f, "ply/fuse_stress", t.fuse_stress);
}

void write_compliance(File& f, const std::string& prefix, const ComplianceFit& fit) {
  f.write(object(prefix), row_major(fit.S), {3, 3});
  f.write(object(prefix + "_se"), row_major(fit.S_se), {3, 3});
  write_count(f, prefix + "_rank", fit.rank);
  write_scalar(f, prefix + "_relative_residual", fit.relative_residual);
  f.write(object(prefix + "_direction_residual"), fit.direction_residual, {fit.direction_residual.size()});
  write_count(f, prefix + "_spd", fit.symmetric_positive_definite ? 1 : 0);
  write_count(f, prefix + "_n_points", fit.n_points);
}

// /law/<name>/: C_c (3×3), q (K×3), beta (K), relative_residual, one_plane_residual,
// struts_residual, direction_residual (one per direction), n_points, ok (1: a fitted law; 0:
// none, attribute message says why); attribute form.
// /law/<name>/polar_deg, polar_E_tension, polar_E_compression (law::PolarModuli), when there are any.
void write_polar(File& f, const std::string& name, const law::PolarModuli& polar) {
  if (polar.empty()) return;
  f.write(object(name + "/polar_deg"), polar.deg, {polar.deg.size()});
  f.write(object(name + "/polar_E_tension"), polar.E_tension, {polar.deg.size()});
  f.write(object(name + "/polar_E_compression"), polar.E_compression, {polar.deg.size()});
}

void write_cone(File& f, const std::string& name, const law::ConeFit& fit, std::size_t n_directions) {
  f.create_group(object(name));
  f.write(object(name + "/C_c"), row_major(fit.law.C_c), {3, 3});
  std::vector<double> q;
  for (const auto& normal : fit.law.q) q.insert(q.end(), normal.data(), normal.data() + 3);
  f.write(object(name + "/q"), q, {fit.law.q.size(), 3});
  f.write(object(name + "/beta"), fit.law.beta, {fit.law.beta.size()});
  write_scalar(f, name + "/relative_residual", fit.relative_residual);
  write_scalar(f, name + "/one_plane_residual", fit.one_plane_residual);
  write_scalar(f, name + "/struts_residual", fit.struts_residual);
  std::vector<double> residual = fit.direction_residual;
  residual.resize(n_directions, std::numeric_limits<double>::quiet_NaN());
  f.write(object(name + "/direction_residual"), residual, {n_directions});
  write_count(f, name + "/n_points", fit.n_points);
  write_count(f, name + "/ok", fit.ok ? 1 : 0);
  f.write_attribute(object(name), "message", fit.message);
  f.write_attribute(object(name), "form", fit.form);
  write_polar(f, name, fit.polar);
}

// Reads /law/<name> with the shape-checked reads of File; refusals name the file and the object.
class Reader {
 public:
  explicit Reader(const File& f) : f_(f) {}

  [[noreturn]] void fail(const std::string& name, const std::string& what) const {
    throw InputError(f_.path().string() + ": " + name + ": " + what);
  }

  std::vector<double> doubles(const std::string& name, const Shape& shape, const char* why = "") const {
    return f_.read_doubles(object(name), shape, why);
  }
  std::vector<std::int64_t> ints(const std::string& name, const Shape& shape, const char* why = "") const {
    return f_.read_ints(object(name), shape, why);
  }
  double scalar(const std::string& name) const { return doubles(name, {1})[0]; }

  int count(const std::string& name, std::int64_t lo, std::int64_t hi) const {
    const std::int64_t v = ints(name, {1})[0];
    if (v < lo || v > hi)
      fail(object(name),
           "value " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v);
  }

  Eigen::Matrix3d matrix(const std::string& name) const {
    const auto v = doubles(name, {3, 3});
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = v[3 * i + j];
    return m;
  }

 private:
  const File& f_;
};

// /law/ply: the ply's nine constants per bond state and sign (law/ply.hpp).
PlyTable read_ply(const Reader& r) {
  PlyTable t;
  const std::vector<std::int64_t> state = r.ints("ply/state", {any_extent});
  const hsize_t n = state.size();
  const std::vector<std::int64_t> sign = r.ints("ply/sign", {n}, " like /law/ply/state");
  const std::vector<std::int64_t> broken = r.ints("ply/broken", {n}, " like /law/ply/state");
  const std::vector<double> constants =
      r.doubles("ply/constants", {n, std::size(ply_constant_fields)}, " like /law/ply/state");
  const std::vector<double> left = r.doubles("ply/sigma33_left", {n}, " like /law/ply/state");
  t.fuse_stress = r.scalar("ply/fuse_stress");
  for (hsize_t i = 0; i < n; ++i) {
    if (state[i] < 0 || state[i] > 2)
      r.fail(object("ply/state"), "value " + std::to_string(state[i]) + " not 0, 1 or 2");
    if (sign[i] != 1 && sign[i] != -1) r.fail(object("ply/sign"), "value " + std::to_string(sign[i]) + " not 1 or -1");
    PlyConstants c;
    c.state = static_cast<PlyState>(state[i]);
    c.sign = static_cast<int>(sign[i]);
    c.broken = static_cast<int>(broken[i]);
    std::size_t k = i * std::size(ply_constant_fields);
    for_each_field(ply_constant_fields, c, [&](const auto&, double& v) { v = constants[k++]; });
    c.sigma33_left = left[i];
    t.rows.push_back(c);
  }
  return t;
}

ComplianceFit read_compliance(const Reader& r, const std::string& prefix, hsize_t n_directions) {
  ComplianceFit fit;
  fit.S = r.matrix(prefix);
  fit.S_se = r.matrix(prefix + "_se");
  // 6 unknowns of the symmetric S.
  fit.rank = r.count(prefix + "_rank", 0, 6);
  fit.relative_residual = r.scalar(prefix + "_relative_residual");
  fit.direction_residual = r.doubles(prefix + "_direction_residual", {n_directions}, " like /law/direction_deg");
  fit.symmetric_positive_definite = r.count(prefix + "_spd", 0, 1) == 1;
  fit.n_points = r.count(prefix + "_n_points", 0, std::numeric_limits<int>::max());
  return fit;
}

law::PolarModuli read_polar(const File& f, const Reader& r, const std::string& name) {
  law::PolarModuli polar;
  if (!f.exists(object(name + "/polar_deg"))) return polar;
  Shape found;
  polar.deg = f.read_doubles(object(name + "/polar_deg"), {any_extent}, "", &found);
  const std::string like = " like " + object(name + "/polar_deg");
  polar.E_tension = r.doubles(name + "/polar_E_tension", {found[0]}, like.c_str());
  polar.E_compression = r.doubles(name + "/polar_E_compression", {found[0]}, like.c_str());
  return polar;
}

law::ConeFit read_cone(const File& f, const Reader& r, const std::string& name, hsize_t n_directions) {
  law::ConeFit fit;
  fit.law.C_c = r.matrix(name + "/C_c");
  Shape found;
  const auto q = f.read_doubles(object(name + "/q"), {any_extent, 3}, "", &found);
  const hsize_t K = found[0];
  if (K < 1 || K > static_cast<hsize_t>(law::max_planes))
    r.fail(object(name + "/q"), std::to_string(K) + " planes, expected 1 to " + std::to_string(law::max_planes));
  fit.law.q.clear();
  for (hsize_t k = 0; k < K; ++k) fit.law.q.emplace_back(q[3 * k], q[3 * k + 1], q[3 * k + 2]);
  fit.law.beta = r.doubles(name + "/beta", {K}, (" like " + object(name + "/q")).c_str());
  fit.relative_residual = r.scalar(name + "/relative_residual");
  fit.one_plane_residual = r.scalar(name + "/one_plane_residual");
  fit.struts_residual = r.scalar(name + "/struts_residual");
  fit.direction_residual = r.doubles(name + "/direction_residual", {n_directions}, " like /law/direction_deg");
  fit.n_points = r.count(name + "/n_points", 0, std::numeric_limits<int>::max());
  fit.ok = r.count(name + "/ok", 0, 1) == 1;
  fit.message = f.read_string_attribute(object(name), "message");
  fit.form = f.read_string_attribute(object(name), "form");
  fit.polar = read_polar(f, r, name);
  // A law a structure code will evaluate: refuse one that is not admissible.
  if (fit.ok) {
    const std::string problem = law::admissibility_problem(fit.law);
    if (!problem.empty()) r.fail(object(name), "the cone-wise law is not admissible: " + problem);
  }
  return fit;
}

// /law/<name>/: a compact law against the exact one or the sweep's held-out directions
// (law/cone_check.hpp; attribute `against`): stress (K×3 unit directions), error (K), max_error,
// rms_error, worst (3), the same of the form fitted to the sweep (sweep_fit_*); for
// /law/cone_check against the exact law also its apparent moduli (polar_*).
void write_cone_check(File& f, const std::string& name, const law::ConeCheck& c) {
  f.create_group(object(name));
  f.write_attribute(object(name), "against", law::checked_against_text(c.against));
  std::vector<double> stress;
  for (const auto& N : c.directions) stress.insert(stress.end(), N.data(), N.data() + 3);
  f.write(object(name + "/stress"), stress, {c.directions.size(), 3});
  f.write(object(name + "/error"), c.error, {c.error.size()});
  write_scalar(f, name + "/max_error", c.max_error);
  write_scalar(f, name + "/rms_error", c.rms_error);
  f.write(object(name + "/worst"), std::vector<double>{c.worst(0), c.worst(1), c.worst(2)}, {3});
  write_scalar(f, name + "/sweep_fit_max_error", c.sweep_fit_max_error);
  write_scalar(f, name + "/sweep_fit_rms_error", c.sweep_fit_rms_error);
  write_polar(f, name, c.polar);
}

law::ConeCheck read_cone_check(const File& f, const Reader& r, const std::string& name) {
  law::ConeCheck c;
  // Written by every version that writes the held-out check; before it, only the exact law.
  if (f.has_attribute(object(name), "against")) {
    const std::string against = f.read_string_attribute(object(name), "against");
    try {
      c.against = law::checked_against_from(against);
    } catch (const std::invalid_argument&) {
      r.fail(object(name), "attribute against is '" + against +
                               "', not 'the exact law', 'held-out sweep directions' or 'held-out full solves'");
    }
  }
  Shape found;
  const auto stress = f.read_doubles(object(name + "/stress"), {any_extent, 3}, "", &found);
  const hsize_t K = found[0];
  for (hsize_t k = 0; k < K; ++k) c.directions.emplace_back(stress[3 * k], stress[3 * k + 1], stress[3 * k + 2]);
  c.error = r.doubles(name + "/error", {K}, (" like " + object(name + "/stress")).c_str());
  c.max_error = r.scalar(name + "/max_error");
  c.rms_error = r.scalar(name + "/rms_error");
  const auto worst = r.doubles(name + "/worst", {3});
  c.worst = {worst[0], worst[1], worst[2]};
  c.sweep_fit_max_error = r.scalar(name + "/sweep_fit_max_error");
  c.sweep_fit_rms_error = r.scalar(name + "/sweep_fit_rms_error");
  c.polar = read_polar(f, r, name);
  return c;
}

}  // namespace

void write_law(const std::filesystem::path& file, const Law& law) {
  const std::size_t n = law.directions.size();
  if (n == 0) throw std::invalid_argument("write_law: the law has no direction");
  for (const auto& m : compliance_members)
    if ((law.*m.fit).direction_residual.size() != n)
      throw std::invalid_argument(std::string("write_law: ") + m.prefix + " direction_residual has " +
                                  std::to_string((law.*m.fit).direction_residual.size()) + " entries for " +
                                  std::to_string(n) + " directions");
  {
    io::File f = io::File::create(file);
    f.create_group(group);
    write_columns(f, group, direction_columns, law.directions);
    for (const auto& m : compliance_members) write_compliance(f, m.prefix, law.*m.fit);
    write_scalar(f, "cone_rank_one_ratio", law.cone_rank_one_ratio);
    write_count(f, "cone_wise_linear", law.cone_wise_linear ? 1 : 0);
    f.write(object("cone_normal"), std::vector<double>{law.cone_normal(0), law.cone_normal(1), law.cone_normal(2)},
            {3});
    write_scalar(f, "cone_beta", law.cone_beta);
    for (const auto& m : law::cone_members) write_cone(f, m.name, law.*m.fit, n);
    write_onset(f, object("onset"), law.onset);
    if (law.cell) {
      write_condensed(f, object("cell"), *law.cell);
      for (const law::CellReplayMember& m : law::cell_replay_members) {
        if (!law::carries(*law.cell, m)) continue;
        f.create_group(object(m.name));
        write_datasets(f, object(m.name), law::cell_replay_fields, law.*m.replay);
      }
    }
    if (!law.ply.rows.empty()) write_ply(f, law.ply);
    if (law.ply.expansion.asked()) {
      f.create_group(object("expansion"));
      write_attributes(f, object("expansion"), law::ply_expansion_fields, law.ply.expansion);
    }
    if (!law.cone_check.directions.empty()) write_cone_check(f, "cone_check", law.cone_check);
    if (!law.cone_after_fuse_check.directions.empty())
      write_cone_check(f, "cone_after_fuse_check", law.cone_after_fuse_check);
    if (law.small) {
      write_condensed(f, object("small"), *law.small);
      f.create_group(object("small_fit"));
      write_datasets(f, object("small_fit"), law::small_cell_fit_fields, law.small_fit);
      write_cone_check(f, "small_check", law.small_check);
      if (law.small_ply_check.directions > 0) {
        f.create_group(object("small_ply_check"));
        write_datasets(f, object("small_ply_check"), law::ply_check_fields, law.small_ply_check);
      }
    }
    f.write_attribute(group, "small_note", law.small_note);
    f.write_attribute(group, "cell_note", law.cell_note);
    f.write_attribute(group, "units", law.units);
    f.write_attribute(group, "stress_state", law.stress_state);
    f.write_attribute(group, "shear_convention", std::string(law::shear_convention));
    write_constituents(f, group, law.constituents);
    write_provenance(f, law::format_name, law.provenance);
    write_output(file, f.close_to_image());
  }
}

Law read_law(const std::filesystem::path& file) {
  const File f = File::open_read(file);
  const Reader r(f);
  check_format(f, law::format_name);
  if (!f.exists(group)) r.fail(group, "missing group");

  Law law;
  const auto directions = f.read_doubles(object("direction_deg"), {any_extent});
  if (directions.empty()) r.fail(object("direction_deg"), "expected a non-empty list of directions, found none");
  const hsize_t n = directions.size();
  for (double theta : directions)
    if (!std::isfinite(theta)) r.fail(object("direction_deg"), "a direction is not finite");
  law.directions.resize(n);
  read_columns(f, group, direction_columns, law.directions, "/law/direction_deg");
  for (const auto& m : compliance_members) law.*m.fit = read_compliance(r, m.prefix, n);
  law.cone_rank_one_ratio = r.scalar("cone_rank_one_ratio");
  law.cone_wise_linear = r.count("cone_wise_linear", 0, 1) == 1;
  const auto normal = r.doubles("cone_normal", {3});
  law.cone_normal = {normal[0], normal[1], normal[2]};
  law.cone_beta = r.scalar("cone_beta");
  for (const auto& m : law::cone_members) law.*m.fit = read_cone(f, r, m.name, n);
  law.onset = read_onset(f, object("onset"));
  if (f.exists(object("cell"))) {
    law.cell = read_condensed(f, object("cell"));
    for (const law::CellReplayMember& m : law::cell_replay_members) {
      if (!law::carries(*law.cell, m)) continue;
      read_datasets(f, object(m.name), law::cell_replay_fields, law.*m.replay);
    }
  }
  if (f.exists(object("ply"))) law.ply = read_ply(r);
  if (f.exists(object("expansion")))
    read_attributes(f, object("expansion"), law::ply_expansion_fields, law.ply.expansion);
  if (f.exists(object("cone_check"))) law.cone_check = read_cone_check(f, r, "cone_check");
  if (f.exists(object("cone_after_fuse_check")))
    law.cone_after_fuse_check = read_cone_check(f, r, "cone_after_fuse_check");
  if (f.exists(object("small"))) {
    law.small = read_condensed(f, object("small"));
    read_datasets(f, object("small_fit"), law::small_cell_fit_fields, law.small_fit);
    law.small_check = read_cone_check(f, r, "small_check");
    if (f.exists(object("small_ply_check"))) {
      read_datasets(f, object("small_ply_check"), law::ply_check_fields, law.small_ply_check);
    }
  }
  // Files of the fit before the small cell have no note.
  if (f.has_attribute(group, "small_note")) law.small_note = f.read_string_attribute(group, "small_note");
  if (!law.small && law.small_note.empty()) law.small_note = "law.h5 gives no reason";
  law.cell_note = f.read_string_attribute(group, "cell_note");
  // Every message that says the law has no exact law quotes the reason: never an empty one.
  if (!law.cell && law.cell_note.empty()) law.cell_note = "law.h5 gives no reason";

  law.units = f.read_string_attribute(group, "units");
  law.stress_state = f.read_string_attribute(group, "stress_state");
  // The only state this format describes; anything else is a different file.
  if (law.stress_state != "plane strain")
    r.fail(group, "attribute stress_state is '" + law.stress_state + "', expected 'plane strain'");
  f.read_string_attribute(group, "shear_convention");
  law.constituents = read_constituents(f, group);
  law.provenance = read_provenance(f, {"scene", "sweep_file", "sweep_hash", "solver_options", "code_version"});
  return law;
}

}  // namespace dualcell::io
