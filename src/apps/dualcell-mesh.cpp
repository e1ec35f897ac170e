// dualcell-mesh: the mesh stage.
//
// Reads a scene, builds the mapped mesh of its block of fibre cells (one fibre and one matrix
// subdomain per cell, each with its own nodes; docs/method.md), writes mesh.h5 (+ mesh.xdmf for
// ParaView) and prints a summary.
//
//   dualcell-mesh --config pipelines/scenes/default.toml --out mesh.h5
#include <cstdio>

#include "apps/options.hpp"
#include "core/scene.hpp"
#include "io/atomic_output.hpp"
#include "io/mesh_file.hpp"
#include "mesh/mesh.hpp"
#include "stage/stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-mesh: mesh a block of fibre cells (fibre disc + matrix square-with-hole per cell)\n"
      "and write mesh.h5 with mesh.xdmf beside it (layout: README.md, \"mesh.h5\")."};
  std::string config, out;
  bool quiet = false;
  app.add_option("--config", config, "scene file (TOML)")->required();
  app.add_option("--out", out, "output HDF5 file; the XDMF file is written beside it")->required();
  app.add_flag("--quiet", quiet, "do not print the summary");
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  return dualcell::run_stage("dualcell-mesh", [&] {
    using namespace dualcell;
    const Scene scene = load_scene(config);
    io::check_outputs({out, io::xdmf_beside(out)}, {config, scene.material_file});
    stage::print_warnings("dualcell-mesh", scene);
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    io::write_mesh(m, scene, out);
    if (quiet) return;
    const Geometry& g = m.geometry;
    std::printf("dualcell-mesh: %s -> %s\n", config.c_str(), out.c_str());
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
  });
}
