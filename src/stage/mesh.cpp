#include "stage/mesh.hpp"

#include <cstdio>

#include "io/atomic_output.hpp"
#include "io/mesh_file.hpp"
#include "stage/stage.hpp"

namespace dualcell::stage {

mesh::Mesh run_mesh(const std::filesystem::path& scene_file, const std::filesystem::path& out) {
  const Scene scene = load_scene(scene_file);
  print_warnings("dualcell-mesh", scene);
  io::check_outputs({out, io::xdmf_beside(out)}, {scene_file, scene.material_file});
  mesh::Mesh m = mesh::build_mesh(scene.geometry);
  io::write_mesh(m, scene, out);
  return m;
}

void print_mesh_summary(const std::filesystem::path& scene_file, const std::filesystem::path& out,
                        const mesh::Mesh& m) {
  const Geometry& g = m.geometry;
  std::printf("dualcell-mesh: %s -> %s\n", scene_file.c_str(), out.c_str());
  std::printf("  cells            %d x %d (cell size %g, fibre radius %g, offset [%g, %g], degree %d, %s)\n",
              g.cells[0], g.cells[1], g.cell_size, g.fibre_radius, g.fibre_offset[0], g.fibre_offset[1], g.degree,
              to_string(g.element));
  std::printf("  subdomains       %zu (%d fibre + %d matrix)\n", m.subdomains.size(), m.n_cells(), m.n_cells());
  std::printf("  nodes            %d\n", m.n_nodes());
  std::printf("  triangles        %zu (%d nodes each)\n", m.triangles.size(), m.triangles.width());
  std::printf("  interface pairs  %zu\n", m.interface_pairs.size());
  std::printf("  glue pairs       %zu\n", m.glue_pairs.size());
  std::printf("  minimum angle    %.2f deg\n", mesh::minimum_angle_deg(m));
  std::printf("  dim u            %d\n", m.dim_u());
}

}  // namespace dualcell::stage
