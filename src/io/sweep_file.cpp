#include "io/sweep_file.hpp"

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/hash.hpp"
#include "io/hdf5.hpp"

namespace dualcell::io {

namespace {

std::string group_of(int index) {
  char name[32];
  std::snprintf(name, sizeof name, "/paths/%03d", index);
  return name;
}

template <typename Get>
std::vector<double> column(const std::vector<sweep::Step>& steps, Get get) {
  std::vector<double> v;
  for (const auto& s : steps) v.push_back(get(s));
  return v;
}

std::vector<double> rows3(const std::vector<sweep::Step>& steps, bool strain) {
  std::vector<double> v;
  for (const auto& s : steps)
    for (int c = 0; c < 3; ++c) v.push_back(strain ? s.strain(c) : s.stress(c));
  return v;
}

void write_path(File& f, const sweep::PathResult& p) {
  const std::string g = group_of(p.spec.index);
  const hsize_t n = p.steps.size();
  f.create_group(g);
  f.write_attribute(g, "direction_deg", p.spec.direction_deg);
  f.write_attribute(g, "sign", std::int64_t{p.spec.sign});
  f.write_attribute(g, "unit_stress", std::vector<double>{p.spec.unit_stress(0), p.spec.unit_stress(1), p.spec.unit_stress(2)});
  f.write_attribute(g, "schedule", p.spec.loads);
  f.write(g + "/load", column(p.steps, [](const auto& s) { return s.load; }), {n});
  f.write(g + "/stress", rows3(p.steps, false), {n, 3});
  f.write(g + "/strain", rows3(p.steps, true), {n, 3});
  std::vector<std::int64_t> broken, outer, ops, converged;
  for (const auto& s : p.steps) {
    broken.push_back(s.broken_bonds);
    outer.push_back(s.outer_iterations);
    ops.push_back(s.operator_applications);
    converged.push_back(s.converged);
  }
  f.write(g + "/broken_bonds", broken, {n});
  f.write(g + "/outer_iterations", outer, {n});
  f.write(g + "/operator_applications", ops, {n});
  f.write(g + "/converged", converged, {n});
  f.write(g + "/kkt_residual", column(p.steps, [](const auto& s) { return s.kkt_residual; }), {n});
  f.write(g + "/seconds", column(p.steps, [](const auto& s) { return s.seconds; }), {n});
  if (p.fuse) {
    const auto& z = *p.fuse;
    f.write(g + "/fuse/onset_load", std::vector<double>{z.onset_load}, {1});
    f.write(g + "/fuse/load_before", std::vector<double>{z.load_before}, {1});
    f.write(g + "/fuse/load_after", std::vector<double>{z.load_after}, {1});
    f.write(g + "/fuse/strain_before", std::vector<double>{z.strain_before(0), z.strain_before(1), z.strain_before(2)}, {3});
    f.write(g + "/fuse/strain_after", std::vector<double>{z.strain_after(0), z.strain_after(1), z.strain_after(2)}, {3});
  }
}

sweep::PathResult read_path(const File& f, int index) {
  const std::string g = group_of(index);
  const std::string where = f.path().string() + ": " + g;
  sweep::PathResult p;
  p.spec.index = index;
  p.spec.direction_deg = f.read_double_attribute(g, "direction_deg").at(0);
  p.spec.sign = static_cast<int>(f.read_int_attribute(g, "sign").at(0));
  const auto unit = f.read_double_attribute(g, "unit_stress");
  if (unit.size() != 3) throw InputError(where + ": attribute unit_stress needs 3 entries");
  p.spec.unit_stress = {unit[0], unit[1], unit[2]};
  p.spec.loads = f.read_double_attribute(g, "schedule");
  // NaN marks a stress_directions path; anything else must be a real path of sign ±1.
  if (std::isinf(p.spec.direction_deg) || (p.spec.sign != 1 && p.spec.sign != -1) || !p.spec.unit_stress.allFinite())
    throw InputError(where + ": attributes direction_deg, sign or unit_stress out of range (truncated or corrupt?)");
  const auto load = f.read_doubles(g + "/load");
  const std::size_t n = load.size();
  auto need = [&](const std::string& name, std::size_t size, std::vector<hsize_t> dims) {
    if (dims.empty() || dims[0] != n || (dims.size() == 2 ? dims[0] * dims[1] : dims[0]) != size)
      throw InputError(where + "/" + name + ": expected " + std::to_string(n) + " rows like /load (truncated or corrupt?)");
  };
  std::vector<hsize_t> dims;
  const auto stress = f.read_doubles(g + "/stress", &dims);
  need("stress", 3 * n, dims);
  const auto strain = f.read_doubles(g + "/strain", &dims);
  need("strain", 3 * n, dims);
  const auto broken = f.read_ints(g + "/broken_bonds", &dims);
  need("broken_bonds", n, dims);
  const auto outer = f.read_ints(g + "/outer_iterations", &dims);
  need("outer_iterations", n, dims);
  const auto ops = f.read_ints(g + "/operator_applications", &dims);
  need("operator_applications", n, dims);
  const auto converged = f.read_ints(g + "/converged", &dims);
  need("converged", n, dims);
  const auto kkt = f.read_doubles(g + "/kkt_residual", &dims);
  need("kkt_residual", n, dims);
  const auto seconds = f.read_doubles(g + "/seconds", &dims);
  need("seconds", n, dims);
  for (std::size_t i = 0; i < n; ++i) {
    // Loads and applied stresses are always finite; strains of a converged step too.
    const auto finite = [&](const std::vector<double>& v, std::size_t from, std::size_t count) {
      for (std::size_t j = from; j < from + count; ++j)
        if (!std::isfinite(v[j])) return false;
      return true;
    };
    if (!finite(load, i, 1)) throw InputError(where + "/load: non-finite load in row " + std::to_string(i));
    if (!finite(stress, 3 * i, 3)) throw InputError(where + "/stress: non-finite stress in row " + std::to_string(i));
    if (converged[i] != 0 && !finite(strain, 3 * i, 3))
      throw InputError(where + "/strain: non-finite strain in converged row " + std::to_string(i));
    sweep::Step s;
    s.load = load[i];
    s.stress = {stress[3 * i], stress[3 * i + 1], stress[3 * i + 2]};
    s.strain = {strain[3 * i], strain[3 * i + 1], strain[3 * i + 2]};
    s.broken_bonds = static_cast<int>(broken[i]);
    s.outer_iterations = outer[i];
    s.operator_applications = ops[i];
    s.converged = converged[i] != 0;
    s.kkt_residual = kkt[i];
    s.seconds = seconds[i];
    p.steps.push_back(s);
  }
  if (f.exists(g + "/fuse")) {
    sweep::Fuse z;
    z.onset_load = f.read_doubles(g + "/fuse/onset_load").at(0);
    z.load_before = f.read_doubles(g + "/fuse/load_before").at(0);
    z.load_after = f.read_doubles(g + "/fuse/load_after").at(0);
    const auto before = f.read_doubles(g + "/fuse/strain_before"), after = f.read_doubles(g + "/fuse/strain_after");
    if (before.size() != 3 || after.size() != 3) throw InputError(where + "/fuse: strain_before/after need 3 entries");
    z.strain_before = {before[0], before[1], before[2]};
    z.strain_after = {after[0], after[1], after[2]};
    p.fuse = z;
  }
  return p;
}

void write_provenance(File& f, const SweepProvenance& p, std::size_t n_paths) {
  f.write_attribute("/", "format", std::string("dualcell sweep 1"));
  f.write_attribute("/", "code_version", p.code_version);
  f.write_attribute("/", "scene", p.scene_text);
  if (!p.material_text.empty()) f.write_attribute("/", "material", p.material_text);
  f.write_attribute("/", "scene_file", p.scene_file);
  f.write_attribute("/", "mesh_file", p.mesh_file);
  f.write_attribute("/", "mesh_hash", p.mesh_hash);
  f.write_attribute("/", "solver_options", p.solver_options);
  f.write_attribute("/", "inputs_key", p.key());
  f.write_attribute("/", "n_paths", static_cast<std::int64_t>(n_paths));
  f.write_attribute("/", "fibre_E", p.fibre_E);
  f.write_attribute("/", "fibre_nu", p.fibre_nu);
  f.write_attribute("/", "matrix_E", p.matrix_E);
  f.write_attribute("/", "matrix_nu", p.matrix_nu);
  f.write_attribute("/", "fibre_volume_fraction", p.fibre_volume_fraction);
}

}  // namespace

std::string SweepProvenance::key() const {
  return text_hash(scene_text + '\0' + material_text + '\0' + mesh_hash + '\0' + solver_options + '\0' + code_version);
}

std::filesystem::path parts_folder(const std::filesystem::path& out) {
  std::filesystem::path folder = out;
  folder += ".parts";
  return folder;
}

void write_part(const std::filesystem::path& out, const sweep::PathResult& path, const SweepProvenance& provenance) {
  const auto folder = parts_folder(out);
  std::filesystem::create_directories(folder);
  char name[32];
  std::snprintf(name, sizeof name, "path-%03d.h5", path.spec.index);
  AtomicOutputs outputs;
  const auto tmp = outputs.add(folder / name);
  {
    File f = File::create(tmp);
    f.create_group("/paths");
    write_path(f, path);
    f.write_attribute("/", "inputs_key", provenance.key());
  }
  outputs.commit();
}

std::optional<sweep::PathResult> read_part(const std::filesystem::path& out, int index,
                                           const SweepProvenance& provenance) {
  char name[32];
  std::snprintf(name, sizeof name, "path-%03d.h5", index);
  const auto file = parts_folder(out) / name;
  if (!std::filesystem::exists(file)) return std::nullopt;
  try {
    const File f = File::open_read(file);
    if (f.read_string_attribute("/", "inputs_key") != provenance.key()) return std::nullopt;
    return read_path(f, index);
  } catch (const InputError&) {
    return std::nullopt;  // a damaged part is recomputed
  }
}

void write_sweep(const std::filesystem::path& out, const std::vector<sweep::PathResult>& paths,
                 const SweepProvenance& provenance) {
  AtomicOutputs outputs;
  const auto tmp = outputs.add(out);
  {
    File f = File::create(tmp);
    f.create_group("/paths");
    for (const auto& p : paths) write_path(f, p);
    write_provenance(f, provenance, paths.size());
  }
  outputs.commit();
  std::error_code ec;
  std::filesystem::remove_all(parts_folder(out), ec);
}

SweepProvenance read_sweep_provenance(const std::filesystem::path& file) {
  const File f = File::open_read(file);
  if (!f.has_attribute("/", "format") || f.read_string_attribute("/", "format") != "dualcell sweep 1")
    throw InputError(file.string() + ": not a dualcell sweep file (root attribute format != \"dualcell sweep 1\")");
  SweepProvenance p;
  p.code_version = f.read_string_attribute("/", "code_version");
  p.scene_text = f.read_string_attribute("/", "scene");
  if (f.has_attribute("/", "material")) p.material_text = f.read_string_attribute("/", "material");
  p.scene_file = f.read_string_attribute("/", "scene_file");
  p.mesh_file = f.read_string_attribute("/", "mesh_file");
  p.mesh_hash = f.read_string_attribute("/", "mesh_hash");
  p.solver_options = f.read_string_attribute("/", "solver_options");
  p.fibre_E = f.read_double_attribute("/", "fibre_E").at(0);
  p.fibre_nu = f.read_double_attribute("/", "fibre_nu").at(0);
  p.matrix_E = f.read_double_attribute("/", "matrix_E").at(0);
  p.matrix_nu = f.read_double_attribute("/", "matrix_nu").at(0);
  p.fibre_volume_fraction = f.read_double_attribute("/", "fibre_volume_fraction").at(0);
  return p;
}

std::vector<sweep::PathResult> read_sweep(const std::filesystem::path& file) {
  const File f = File::open_read(file);
  if (!f.has_attribute("/", "format") || f.read_string_attribute("/", "format") != "dualcell sweep 1")
    throw InputError(file.string() + ": not a dualcell sweep file (root attribute format != \"dualcell sweep 1\")");
  const auto n = f.read_int_attribute("/", "n_paths").at(0);
  if (n < 1)
    throw InputError(file.string() + ": attribute n_paths = " + std::to_string(n) + ": a sweep has at least one path");
  std::vector<sweep::PathResult> paths;
  for (int i = 0; i < n; ++i) {
    if (!f.exists(group_of(i)))
      throw InputError(file.string() + ": " + group_of(i) + ": missing (the file says n_paths = " + std::to_string(n) + ")");
    paths.push_back(read_path(f, i));
  }
  return paths;
}

}  // namespace dualcell::io
