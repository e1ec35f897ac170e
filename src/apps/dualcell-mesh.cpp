// dualcell-mesh: the mesh stage.
//
// Reads a scene, builds the mapped mesh of its block of fibre cells (one fibre and one matrix
// subdomain per cell, each with its own nodes; docs/method.md) or the gmsh mesh of its periodic
// RVE (fibre pieces and METIS parts of the matrix, rve/mesher.hpp), writes mesh.h5 (+ mesh.xdmf
// for ParaView) and prints a summary.
//
//   dualcell-mesh --config pipelines/scenes/default.toml --out mesh.h5

#include "apps/options.hpp"
#include "stage/mesh.hpp"
#include "stage/stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-mesh: mesh a block of fibre cells (fibre disc + matrix square-with-hole per cell),\n"
      "or a periodic RVE ([geometry] size) with gmsh and METIS, and write mesh.h5 with mesh.xdmf\n"
      "beside it (layout: docs/reference/mesh-h5.md)."};
  std::string config, out;
  bool quiet = false;
  app.add_option("--config", config, "scene file (TOML)")->required();
  app.add_option("--out", out, "output HDF5 file; the XDMF file is written beside it")->required();
  app.add_flag("--quiet", quiet, "do not print the summary");
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  return dualcell::run_stage("dualcell-mesh", [&] {
    dualcell::rve::MeshReport report;
    const dualcell::mesh::Mesh mesh = dualcell::stage::run_mesh(config, out, &report);
    if (!quiet) dualcell::stage::print_mesh_summary(config, out, mesh, report);
  });
}
