#include "io/sweep_file.hpp"

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/text.hpp"
#include "io/atomic_output.hpp"
#include "io/condensed_group.hpp"
#include "io/fields_io.hpp"
#include "io/file_root.hpp"
#include "io/hdf5.hpp"
#include "io/onset_group.hpp"

namespace dualcell::io {

namespace {

std::string group_of(int index) {
  char name[32];
  std::snprintf(name, sizeof name, "/paths/%03d", index);
  return name;
}

void write_path(File& f, const sweep::PathResult& p) {
  const std::string g = group_of(p.spec.index);
  const hsize_t n = p.steps.size();
  f.create_group(g);
  f.write_attribute(g, "direction_deg", p.spec.direction_deg);
  f.write_attribute(g, "sign", std::int64_t{p.spec.sign});
  f.write_attribute(g, "sphere", std::int64_t{p.spec.sphere ? 1 : 0});
  const Eigen::Vector3d N = p.spec.state.in_plane();
  f.write_attribute(g, "unit_stress", std::vector<double>{N(0), N(1), N(2)});
  f.write_attribute(g, "schedule", p.spec.loads);
  write_columns(f, g, step_columns, p.steps);
  // A path with a strain along the fibres: that strain and σ33 per step (left out of every other
  // path, whose files stay as they were).
  if (p.spec.state.eps33() != 0) {
    f.write_attribute(g, "eps33", p.spec.state.eps33());
    std::vector<double> zz;
    for (const auto& s : p.steps) zz.push_back(s.stress_zz);
    f.write(g + "/stress_zz", zz, {n});
  }
  // A path with shears along the fibres: Γ and ⟨τ⟩ per step (likewise only there).
  if (const Eigen::Vector2d gamma = p.spec.state.gamma(); !gamma.isZero(0)) {
    f.write_attribute(g, "gamma", std::vector<double>{gamma(0), gamma(1)});
    std::vector<double> tau;
    for (const auto& s : p.steps) tau.insert(tau.end(), s.shear_stress.data(), s.shear_stress.data() + 2);
    f.write(g + "/shear_stress", tau, {n, 2});
  }
  if (p.fuse) write_datasets(f, g + "/fuse", fuse_fields, *p.fuse);
}

sweep::PathResult read_path(const File& f, int index) {
  const std::string g = group_of(index);
  const std::string where = f.path().string() + ": " + g;
  sweep::PathResult p;
  p.spec.index = index;
  p.spec.direction_deg = f.read_double_attribute_value(g, "direction_deg");
  p.spec.sign = static_cast<int>(f.read_int_attribute_value(g, "sign"));
  const std::int64_t sphere = f.read_int_attribute_value(g, "sphere");
  if (sphere != 0 && sphere != 1)
    throw InputError(where + ": attribute sphere = " + std::to_string(sphere) + ", not 0 or 1");
  p.spec.sphere = sphere == 1;
  const auto unit = f.read_double_attribute(g, "unit_stress", 3);
  p.spec.state = MacroState::stress(Eigen::Vector3d(unit[0], unit[1], unit[2]));
  p.spec.loads = f.read_double_attribute(g, "schedule");
  // NaN marks a stress_directions path; anything else must be a real path of sign ±1.
  if (std::isinf(p.spec.direction_deg) || (p.spec.sign != 1 && p.spec.sign != -1) ||
      !p.spec.state.in_plane().allFinite())
    throw InputError(where + ": attributes direction_deg, sign or unit_stress out of range (truncated or corrupt?)");
  const hsize_t n = f.read_doubles(g + "/load", {any_extent}).size();
  p.steps.resize(n);
  read_columns(f, g, step_columns, p.steps, g + "/load");
  if (f.has_attribute(g, "eps33")) {
    const double eps33 = f.read_double_attribute_value(g, "eps33");
    if (!std::isfinite(eps33) || eps33 == 0)
      throw InputError(where + ": attribute eps33 = " + shortest(eps33) + ", not a finite non-zero strain");
    p.spec.state.hold(MacroState::zz, eps33);
    const auto zz = f.read_doubles(g + "/stress_zz", {n}, " like " + g + "/load");
    for (hsize_t i = 0; i < n; ++i) p.steps[i].stress_zz = zz[i];
  }
  if (f.has_attribute(g, "gamma")) {
    const auto gamma = f.read_double_attribute(g, "gamma", 2);
    const Eigen::Vector2d held(gamma[0], gamma[1]);
    if (!held.allFinite() || held.isZero(0))
      throw InputError(where + ": attribute gamma = " + shortest(gamma) + ", not finite shears, not both 0");
    p.spec.state.hold_shear(held);
    const auto tau = f.read_doubles(g + "/shear_stress", {n, 2}, " like " + g + "/load");
    for (hsize_t i = 0; i < n; ++i) p.steps[i].shear_stress = {tau[2 * i], tau[2 * i + 1]};
  }
  // Loads and applied stresses are always finite; strains of a converged step too, and its
  // stress along the fibres (a path with eps33) and its shear stresses (a path with gamma).
  const bool zz = p.spec.state.eps33() != 0, shear = !p.spec.state.gamma().isZero(0);
  for (hsize_t i = 0; i < n; ++i) {
    const sweep::Step& s = p.steps[i];
    if (!std::isfinite(s.load)) throw InputError(where + "/load: non-finite load in row " + std::to_string(i));
    if (!s.stress.allFinite()) throw InputError(where + "/stress: non-finite stress in row " + std::to_string(i));
    if (s.converged && !s.strain.allFinite())
      throw InputError(where + "/strain: non-finite strain in converged row " + std::to_string(i));
    if (s.converged && zz && !std::isfinite(s.stress_zz))
      throw InputError(where + "/stress_zz: non-finite stress in converged row " + std::to_string(i));
    if (s.converged && shear && !s.shear_stress.allFinite())
      throw InputError(where + "/shear_stress: non-finite stress in converged row " + std::to_string(i));
  }
  if (f.exists(g + "/fuse")) {
    sweep::Fuse z;
    read_datasets(f, g + "/fuse", fuse_fields, z);
    p.fuse = z;
  }
  return p;
}

// A dataset of a check (every row a converged solve): refused with the row of its first
// non-finite value.
void check_finite(const File& f, const std::string& name, const std::vector<double>& values, std::size_t columns) {
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]))
      throw InputError(f.path().string() + ": " + name + ": non-finite value in row " + std::to_string(k / columns));
}

// /longitudinal_check: stress (N×3), eps33 (N), strain (N×3), stress_zz (N), broken (N; absent in
// a file written before the points past the fuse: 0).
void write_longitudinal_points(File& f, const std::vector<sweep::LongitudinalPoint>& points) {
  const auto n = static_cast<hsize_t>(points.size());
  std::vector<double> stress, eps33, strain, zz;
  std::vector<std::int64_t> broken;
  for (const sweep::LongitudinalPoint& p : points) {
    broken.push_back(p.broken);
    stress.insert(stress.end(), p.stress.data(), p.stress.data() + 3);
    strain.insert(strain.end(), p.strain.data(), p.strain.data() + 3);
    eps33.push_back(p.eps33);
    zz.push_back(p.stress_zz);
  }
  f.create_group("/longitudinal_check");
  f.write("/longitudinal_check/stress", stress, {n, 3});
  f.write("/longitudinal_check/eps33", eps33, {n});
  f.write("/longitudinal_check/strain", strain, {n, 3});
  f.write("/longitudinal_check/stress_zz", zz, {n});
  f.write("/longitudinal_check/broken", broken, {n});
}

std::vector<sweep::LongitudinalPoint> read_longitudinal_points(const File& f) {
  const std::string g = "/longitudinal_check";
  const std::vector<double> eps33 = f.read_doubles(g + "/eps33", {any_extent});
  const hsize_t n = eps33.size();
  const std::string like = " like " + g + "/eps33";
  const std::vector<double> stress = f.read_doubles(g + "/stress", {n, 3}, like);
  const std::vector<double> strain = f.read_doubles(g + "/strain", {n, 3}, like);
  const std::vector<double> zz = f.read_doubles(g + "/stress_zz", {n}, like);
  const std::vector<std::int64_t> broken =
      f.exists(g + "/broken") ? f.read_ints(g + "/broken", {n}, like) : std::vector<std::int64_t>(n, 0);
  std::vector<sweep::LongitudinalPoint> points(n);
  // Every check is a converged solve: all its numbers finite.
  check_finite(f, g + "/eps33", eps33, 1);
  check_finite(f, g + "/stress", stress, 3);
  check_finite(f, g + "/strain", strain, 3);
  check_finite(f, g + "/stress_zz", zz, 1);
  for (hsize_t i = 0; i < n; ++i) {
    if (broken[i] < 0) throw InputError(f.path().string() + ": " + g + "/broken: row " + std::to_string(i) + " < 0");
    points[i].broken = broken[i];
    points[i].stress = Eigen::Vector3d(stress[3 * i], stress[3 * i + 1], stress[3 * i + 2]);
    points[i].strain = Eigen::Vector3d(strain[3 * i], strain[3 * i + 1], strain[3 * i + 2]);
    points[i].eps33 = eps33[i];
    points[i].stress_zz = zz[i];
  }
  return points;
}

// /shear_check: path (N), gamma (N×2), tau (N×2), broken (N).
void write_shear_points(File& f, const std::vector<sweep::ShearPoint>& points) {
  const auto n = static_cast<hsize_t>(points.size());
  std::vector<std::int64_t> path, broken;
  std::vector<double> gamma, tau;
  for (const sweep::ShearPoint& p : points) {
    path.push_back(p.path);
    broken.push_back(p.broken);
    gamma.insert(gamma.end(), p.gamma.data(), p.gamma.data() + 2);
    tau.insert(tau.end(), p.tau.data(), p.tau.data() + 2);
  }
  f.create_group("/shear_check");
  f.write("/shear_check/path", path, {n});
  f.write("/shear_check/gamma", gamma, {n, 2});
  f.write("/shear_check/tau", tau, {n, 2});
  f.write("/shear_check/broken", broken, {n});
}

std::vector<sweep::ShearPoint> read_shear_points(const File& f) {
  const std::string g = "/shear_check";
  const std::vector<std::int64_t> path = f.read_ints(g + "/path", {any_extent});
  const hsize_t n = path.size();
  const std::string like = " like " + g + "/path";
  const std::vector<double> gamma = f.read_doubles(g + "/gamma", {n, 2}, like);
  const std::vector<double> tau = f.read_doubles(g + "/tau", {n, 2}, like);
  const std::vector<std::int64_t> broken = f.read_ints(g + "/broken", {n}, like);
  std::vector<sweep::ShearPoint> points(n);
  check_finite(f, g + "/gamma", gamma, 2);
  check_finite(f, g + "/tau", tau, 2);
  for (hsize_t i = 0; i < n; ++i) {
    if (path[i] < 0 || path[i] > std::numeric_limits<int>::max() || broken[i] < 0 ||
        broken[i] > std::numeric_limits<int>::max())
      throw InputError(f.path().string() + ": " + g + ": row " + std::to_string(i) + ": a path or count out of range");
    points[i].path = static_cast<int>(path[i]);
    points[i].broken = static_cast<int>(broken[i]);
    points[i].gamma = Eigen::Vector2d(gamma[2 * i], gamma[2 * i + 1]);
    points[i].tau = Eigen::Vector2d(tau[2 * i], tau[2 * i + 1]);
  }
  return points;
}

void write_header(File& f, const SweepHeader& header, std::size_t n_paths) {
  write_provenance(f, sweep_format, header.provenance);
  f.write_attribute("/", "inputs_key", inputs_key(header));
  f.write_attribute("/", "n_paths", static_cast<std::int64_t>(n_paths));
  write_constituents(f, "/", header.constituents);
  write_onset(f, "/onset", header.onset);
  if (header.cell) write_condensed(f, "/cell", *header.cell);
  f.write_attribute("/", "cell_note", header.cell_note);
  if (header.cell_basis) write_condensed(f, "/cell_basis", *header.cell_basis);
  if (!header.cell_basis_note.empty()) f.write_attribute("/", "cell_basis_note", header.cell_basis_note);
  if (!header.longitudinal_points.empty()) write_longitudinal_points(f, header.longitudinal_points);
  if (!header.shear_points.empty()) write_shear_points(f, header.shear_points);
  if (header.expansion.asked()) {
    f.create_group("/expansion");
    write_attributes(f, "/expansion", law::ply_expansion_fields, header.expansion);
  }
  if (header.delta_T != 0) f.write_attribute("/", "delta_T", header.delta_T);
  f.write_attribute("/", "qp_tolerance", header.qp_tolerance);
}

}  // namespace

std::string inputs_key(const SweepHeader& header) {
  const Provenance& p = header.provenance;
  return text_hash(p.scene_text + '\0' + p.material_text + '\0' + p.mesh_hash + '\0' + p.solver_options + '\0' +
                   p.code_version);
}

std::filesystem::path parts_folder(const std::filesystem::path& out) {
  std::filesystem::path folder = out;
  folder += ".parts";
  return folder;
}

void write_part(const std::filesystem::path& out, const sweep::PathResult& path, const SweepHeader& header) {
  const auto folder = parts_folder(out);
  std::filesystem::create_directories(folder);
  char name[32];
  std::snprintf(name, sizeof name, "path-%03d.h5", path.spec.index);
  File f = File::create(folder / name);
  f.create_group("/paths");
  write_path(f, path);
  f.write_attribute("/", "inputs_key", inputs_key(header));
  write_output(folder / name, f.close_to_image());
}

std::optional<sweep::PathResult> read_part(const std::filesystem::path& out, int index, const SweepHeader& header) {
  char name[32];
  std::snprintf(name, sizeof name, "path-%03d.h5", index);
  const auto file = parts_folder(out) / name;
  if (!std::filesystem::exists(file)) return std::nullopt;
  try {
    const File f = File::open_read(file);
    if (f.read_string_attribute("/", "inputs_key") != inputs_key(header)) return std::nullopt;
    return read_path(f, index);
  } catch (const InputError&) {
    return std::nullopt;  // a damaged part is recomputed
  }
}

void write_sweep(const std::filesystem::path& out, const std::vector<sweep::PathResult>& paths,
                 const SweepHeader& header) {
  {
    File f = File::create(out);
    f.create_group("/paths");
    for (const auto& p : paths) write_path(f, p);
    write_header(f, header, paths.size());
    write_output(out, f.close_to_image());
  }
  std::error_code ec;
  std::filesystem::remove_all(parts_folder(out), ec);
}

SweepHeader read_sweep_header(const std::filesystem::path& file) {
  const File f = File::open_read(file);
  check_format(f, sweep_format);
  SweepHeader header;
  header.provenance =
      read_provenance(f, {"code_version", "scene", "scene_file", "mesh_file", "mesh_hash", "solver_options"});
  header.constituents = read_constituents(f, "/");
  header.onset = read_onset(f, "/onset");
  if (f.exists("/cell")) header.cell = read_condensed(f, "/cell");
  if (f.has_attribute("/", "cell_note")) header.cell_note = f.read_string_attribute("/", "cell_note");
  if (f.exists("/cell_basis")) header.cell_basis = read_condensed(f, "/cell_basis");
  if (f.has_attribute("/", "cell_basis_note")) header.cell_basis_note = f.read_string_attribute("/", "cell_basis_note");
  if (f.exists("/longitudinal_check")) header.longitudinal_points = read_longitudinal_points(f);
  if (f.exists("/shear_check")) header.shear_points = read_shear_points(f);
  if (f.exists("/expansion")) read_attributes(f, "/expansion", law::ply_expansion_fields, header.expansion);
  if (f.has_attribute("/", "delta_T")) header.delta_T = f.read_double_attribute_value("/", "delta_T");
  if (f.has_attribute("/", "qp_tolerance")) header.qp_tolerance = f.read_double_attribute_value("/", "qp_tolerance");
  return header;
}

std::vector<sweep::PathResult> read_sweep(const std::filesystem::path& file) {
  const File f = File::open_read(file);
  check_format(f, sweep_format);
  const auto n = f.read_int_attribute_value("/", "n_paths");
  if (n < 1)
    throw InputError(file.string() + ": attribute n_paths = " + std::to_string(n) + ": a sweep has at least one path");
  std::vector<sweep::PathResult> paths;
  for (int i = 0; i < n; ++i) {
    if (!f.exists(group_of(i)))
      throw InputError(file.string() + ": " + group_of(i) + ": missing (the file says n_paths = " + std::to_string(n) +
                       ")");
    paths.push_back(read_path(f, i));
  }
  return paths;
}

}  // namespace dualcell::io
