#include "stage/mesh.hpp"

#include <cstdio>

#include "io/atomic_output.hpp"
#include "io/mesh_file.hpp"
#include "rve/mesher.hpp"
#include "stage/stage.hpp"

namespace dualcell::stage {

mesh::Mesh run_mesh(const std::filesystem::path& scene_file, const std::filesystem::path& out,
                    rve::MeshReport* report) {
  const Scene scene = load_scene(scene_file);
  print_warnings("dualcell-mesh", scene);
  io::check_outputs({out, io::xdmf_beside(out)}, {scene_file, scene.material_file});
  mesh::Mesh m = scene.geometry.rve()
                     ? rve::build_rve_mesh(scene.geometry, scene.solver.subdomain_dofs, scene_file.string(), report)
                     : mesh::build_mesh(scene.geometry);
  io::write_mesh(m, scene, out);
  return m;
}

void print_mesh_summary(const std::filesystem::path& scene_file, const std::filesystem::path& out, const mesh::Mesh& m,
                        const rve::MeshReport& report) {
  const Geometry& g = m.geometry;
  std::printf("dualcell-mesh: %s -> %s\n", scene_file.c_str(), out.c_str());
  int fibres = 0;
  for (const auto& s : m.subdomains) fibres += s.is_fibre ? 1 : 0;
  const int matrix = static_cast<int>(m.subdomains.size()) - fibres;
  if (g.rve()) {
    const rve::Statistics& f = report.fibres;
    std::printf("  RVE              %g x %g, %s fibres, degree %d, %s, element size %.4g (gmsh %.2f s, METIS %.3f s)\n",
                g.size[0], g.size[1], to_string(g.layout), g.degree, to_string(g.element), report.element_size,
                report.seconds_gmsh, report.seconds_split);
    std::printf("  fibres           %d, volume fraction %.4f, %d crossing an edge\n", f.fibres, f.volume_fraction,
                f.crossing_edges);
    std::printf("  nearest centres  mean %.4g, sd %.3g, min %.4g; smallest gap %.3g, to an edge %.3g\n",
                f.neighbour_mean, f.neighbour_sd, f.neighbour_min, f.gap_min, f.edge_gap_min);
  } else {
    std::printf("  cells            %d x %d (cell size %g, fibre radius %g, offset [%g, %g], degree %d, %s)\n",
                g.cells[0], g.cells[1], g.cell_size, g.fibre_radius, g.fibre_offset[0], g.fibre_offset[1], g.degree,
                to_string(g.element));
  }
  std::printf("  subdomains       %zu (%d fibre + %d matrix)\n", m.subdomains.size(), fibres, matrix);
  std::printf("  nodes            %d\n", m.n_nodes());
  std::printf("  triangles        %zu (%d nodes each)\n", m.triangles.size(), m.triangles.width());
  std::printf("  interface pairs  %zu\n", m.interface_pairs.size());
  std::printf("  glue pairs       %zu\n", m.glue_pairs.size());
  std::printf("  minimum angle    %.2f deg\n", mesh::minimum_angle_deg(m));
  std::printf("  dim u            %d\n", m.dim_u());
}

}  // namespace dualcell::stage
