#include "io/structure_file.hpp"

#include <cstdio>

#include "io/atomic_output.hpp"
#include "io/fields_io.hpp"
#include "io/file_root.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace dualcell::io {

namespace {

std::string step_group(std::size_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "/steps/%03zu", k);
  return name;
}

}  // namespace

void write_structure(const std::filesystem::path& out, const structure::StructureMesh& mesh,
                     const std::vector<structure::StepResult>& steps, double first_fuse_factor,
                     const std::string& law_form, const std::string& bond_unit, const Provenance& provenance) {
  const hsize_t N = static_cast<hsize_t>(mesh.nodes.rows()), T = static_cast<hsize_t>(mesh.triangles.rows());
  const hsize_t per = static_cast<hsize_t>(mesh.triangles.cols()), S = steps.size();
  const std::filesystem::path xdmf = xdmf_beside(out);
  AtomicOutputs outputs;
  outputs.add(out);
  outputs.add(xdmf);
  {
    File f = File::create(out);
    write_provenance(f, structure_format, provenance);
    f.write_attribute("/", "law_form", law_form);
    if (!bond_unit.empty()) f.write_attribute("/", "bond_unit", bond_unit);
    f.create_group("/mesh");
    std::vector<double> nodes;
    for (hsize_t i = 0; i < N; ++i) nodes.push_back(mesh.nodes(i, 0)), nodes.push_back(mesh.nodes(i, 1));
    f.write("/mesh/nodes", nodes, {N, 2});
    std::vector<std::int64_t> triangles;
    for (hsize_t t = 0; t < T; ++t)
      for (hsize_t k = 0; k < per; ++k) triangles.push_back(mesh.triangles(t, k));
    f.write("/mesh/triangles", triangles, {T, per});
    f.write("/mesh/cell", std::vector<std::int64_t>(mesh.cell.begin(), mesh.cell.end()), {T});
    f.write_attribute("/mesh", "element", std::string(per == 3 ? "p1" : "p2"));

    // Per step: the report as columns (structure_step_columns, the reactions), the fields in
    // /steps/NNN.
    f.create_group("/steps");
    f.write_attribute("/steps", "first_fuse_factor", first_fuse_factor);
    write_columns(f, "/steps", structure_step_columns, steps);
    std::vector<double> reactions;
    for (const auto& s : steps)
      for (const auto& R : s.reactions) reactions.push_back(R(0)), reactions.push_back(R(1));
    f.write("/steps/reactions", reactions, {S, 10});
    std::vector<XdmfGrid> grids;
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const auto& s = steps[k];
      const std::string g = step_group(k);
      f.create_group(g);
      f.write_attribute(g, "factor", s.factor);
      f.write(g + "/displacement", std::vector<double>(s.u.data(), s.u.data() + s.u.size()), {N, 2});
      std::vector<double> stress;
      for (hsize_t t = 0; t < T; ++t)
        for (int c = 0; c < 3; ++c) stress.push_back(s.stress(t, c));
      f.write(g + "/stress", stress, {T, 3});
      f.write(g + "/open", std::vector<std::int64_t>(s.open.begin(), s.open.end()), {T});
      f.write(g + "/fused", std::vector<std::int64_t>(s.fused.begin(), s.fused.end()), {T});
      if (!s.broken.empty()) f.write(g + "/broken", std::vector<double>(s.broken.begin(), s.broken.end()), {T});
      XdmfGrid grid;
      grid.name = "step " + std::to_string(k) + " (factor " + std::to_string(s.factor) + ")";
      grid.nodes_dataset = "/mesh/nodes";
      grid.n_nodes = N;
      grid.triangles_dataset = "/mesh/triangles";
      grid.n_triangles = T;
      grid.nodes_per_triangle = static_cast<int>(per);
      grid.fields = {{"displacement", g + "/displacement", false, {N, 2}},
                     {"stress", g + "/stress", true, {T, 3}},
                     {"open", g + "/open", true, {T}, true},
                     {"fused", g + "/fused", true, {T}, true},
                     {"cell", "/mesh/cell", true, {T}, true}};
      if (!s.broken.empty()) grid.fields.push_back({"broken", g + "/broken", true, {T}});
      grids.push_back(grid);
    }
    outputs.write(out, f.close_to_image());
    outputs.write(xdmf, xdmf_text(out.filename().string(), grids));
  }
  outputs.commit();
}

}  // namespace dualcell::io
