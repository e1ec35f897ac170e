// dualcell-structure: a structure of homogeneous cells with the fitted law.
//
// A rectangle of nx × ny cells (the fitted cell's size), each meshed with m × m squares of two
// p1 or p2 triangles, every element with the cell's exact law (every quadrature point a cell
// with its own bond history) or its cone-wise law and the fuse: a cell whose average stress
// leaves the onset surface switches to the law past the fuse, irreversibly.
// Edge conditions, supports, point loads and load steps from structure.toml (keys:
// docs/reference/scene-keys.md); Newton with a line search per step. Writes structure.h5 and
// structure.xdmf (layout: docs/reference/structure-h5.md).
//
//   dualcell-structure --config structure.toml --law law.h5 --out structure.h5 [--form cell|small|cone]
#include <cstdio>

#include "apps/options.hpp"
#include "stage/stage.hpp"
#include "stage/structure.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-structure: solve a structure of homogeneous cells with the cell's exact law (or its cone-wise\n"
      "law and fuse), and write structure.h5 + structure.xdmf (layout: docs/reference/structure-h5.md)."};
  dualcell::stage::StructureOptions options;
  std::string config, law, out;
  bool quiet = false;
  app.add_option("--config", config, "structure scene (TOML)")->required();
  app.add_option("--law", law, "law.h5 written by dualcell-fit")->required();
  app.add_option("--out", out, "output HDF5 file (the XDMF is written beside it)")->required();
  app.add_option("--form", options.form,
                 "cell: the exact law (/law/cell, every quadrature point a cell with its bond history); small: its "
                 "small cell (/law/small, the same way); cone: the cone-wise law with the fuse per cell; default: cell "
                 "where law.h5 has it, else cone")
      ->check(CLI::IsMember(dualcell::law_forms()));
  app.add_flag("--quiet", quiet, "no progress and no summary");
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  int exit_code = dualcell::exit_ok;
  const int status = dualcell::run_stage("dualcell-structure", [&] {
    using namespace dualcell;
    options.scene_file = config;
    options.law_file = law;
    options.out = out;
    options.progress = !quiet;
    const stage::StructureSummary s = stage::run_structure(options);
    // A step that did not converge (or whose energy is not finite) is in structure.h5, marked
    // in /steps/converged; the stage says so once and exits with the not-converged code.
    int failed = 0;
    for (const auto& r : s.steps) {
      failed += !r.converged;
      if (!r.message.empty())
        std::fprintf(stderr, "dualcell-structure: load factor %g: %s\n", r.factor, r.message.c_str());
    }
    if (failed > 0) {
      exit_code = exit_not_converged;
      std::fprintf(stderr,
                   "dualcell-structure: warning: %d of %zu load steps did not converge (residual or energy not "
                   "finite, or Newton/fuse rounds exhausted); output written, /steps/converged marks them\n",
                   failed, s.steps.size());
    }
    if (quiet) return;
    std::printf("dualcell-structure: %s -> %s: %d cells of size %g, %d nodes, %d triangles, %.2f s\n", config.c_str(),
                out.c_str(), s.n_cells, s.cell_size, s.n_nodes, s.n_triangles, s.seconds);
    if (!s.fuse_note.empty()) std::printf("  %s\n", s.fuse_note.c_str());
    const bool cell = s.law_form == "cell" || s.law_form == "small";
    if (cell)
      std::printf("  law: %s at every quadrature point, the bonds of its %s\n",
                  s.law_form == "cell" ? "exact (/law/cell)" : "the small cell (/law/small)", s.bond_unit.c_str());
    else
      std::printf("  law: cone-wise (/law/cone), the fuse per cell\n");
    std::printf("  first %s at load factor %.6g\n", cell ? "bond breaks" : "cell fuses", s.first_fuse_factor);
    std::printf("  %8s %8s %8s %8s %8s %14s %14s %14s %14s\n", "factor", "newton", "rounds", cell ? "broke" : "fused",
                "open", "energy", "decrease", "watch ux", "watch uy");
    for (const auto& r : s.steps)
      std::printf("  %8.4g %8d %8d %8d %8d %14.6e %14.6e %14.6e %14.6e%s\n", r.factor, r.newton_steps, r.fuse_rounds,
                  cell ? r.newly_broken_units : r.newly_fused_cells, r.open_triangles, r.energy, r.energy_decrease,
                  r.watch_displacement(0), r.watch_displacement(1), r.converged ? "" : "  NOT converged");
    if (cell) {
      std::printf("  (broke: %ss where a bond broke; open: triangles with an open gap at a point, of %d)\n",
                  s.bond_unit.c_str(), s.n_triangles);
      std::printf("  %ss with a broken bond at the end: %d of %d\n", s.bond_unit.c_str(), s.broken_units, s.n_units);
    } else {
      std::printf("  (open: triangles with a plane of the law open at the centroid, of %d)\n", s.n_triangles);
      std::printf("  fused cells at the end: %d of %d\n", s.fused_cells, s.n_cells);
    }
  });
  return status != dualcell::exit_ok ? status : exit_code;
}
