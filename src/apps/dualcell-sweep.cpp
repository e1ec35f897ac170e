// dualcell-sweep: load paths in magnitude and direction through the dual solver.
//
// For every path of the scene ([sweep] directions_deg × {tension, compression}, and the
// general stress_directions), steps through the magnitudes from the intact, unloaded state,
// carrying the bond state, inserting the exact debond onset and bracketing every jump (the
// fuse) by bisection. Setup (assembly, factorisations) is done once for the whole sweep.
// Finished paths are journaled in <out>.parts/, so an interrupted run resumes; the final
// sweep.h5 appears complete at the end.
//
//   dualcell-sweep --config scene.toml --mesh mesh.h5 --out sweep.h5
#include <chrono>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <sstream>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "core/version.hpp"
#include "core/error.hpp"
#include "core/scene.hpp"
#include "core/stage.hpp"
#include "feti/solver.hpp"
#include "io/atomic_output.hpp"
#include "io/hash.hpp"
#include "io/mesh_file.hpp"
#include "io/sweep_file.hpp"
#include "sweep/sweep.hpp"

namespace {

std::string solver_options(const dualcell::Scene& scene) {
  const auto& s = scene.solver;
  std::ostringstream o;
  o.precision(17);
  o << "tolerance=" << s.tolerance << "; max_outer_iterations=" << s.max_outer_iterations
    << "; max_operator_applications=" << s.max_operator_applications << "; rho_factor=" << s.rho_factor << "; rho_growth=" << s.rho_growth << "; rho_patience=" << s.rho_patience
    << "; Gamma=" << s.Gamma << "; max_debond_rounds=" << s.max_debond_rounds
    << "; preconditioner=" << to_string(s.preconditioner)
    << "; fuse_tolerance=" << scene.sweep.fuse_tolerance;
  return o.str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dualcell-sweep: sweep load paths (directions x tension/compression x magnitudes) with bond history\n"
               "and the fuse; writes sweep.h5 (layout: README.md, \"sweep.h5\"). Resumes an interrupted run."};
  std::string config, mesh_file, out;
  bool quiet = false;
  long interrupt_after = 0;
  app.add_option("--config", config, "scene file (TOML)")->required();
  app.add_option("--mesh", mesh_file, "mesh.h5 made by dualcell-mesh from the same scene")->required();
  app.add_option("--out", out, "output HDF5 file")->required();
  app.add_flag("--quiet", quiet, "no progress on stderr");
  int threads = 0;
  app.add_option("--threads", threads, "threads for the subdomain work; 0 = OMP_NUM_THREADS or all cores (results do not depend on it)")
      ->check(CLI::Range(0, 4096));
  // For tests of the resume: stop dead (as kill -9 would) after this many finished paths.
  app.add_option("--interrupt-after-paths", interrupt_after, "")->group("");
  CLI11_PARSE(app, argc, argv);

  return dualcell::run_stage("dualcell-sweep", [&] {
    using namespace dualcell;
    const Scene scene = load_scene(config);
    for (const auto& w : scene.warnings) std::fprintf(stderr, "dualcell-sweep: warning: %s\n", w.c_str());
    const io::MeshFile mesh_in = io::read_mesh(mesh_file);
    const std::string mismatch = io::geometry_mismatch(mesh_in.mesh, scene);
    if (!mismatch.empty())
      throw InputError(mesh_file + ": made from a different scene than " + config + ": " + mismatch);
    const std::vector<sweep::PathSpec> specs = sweep::plan_paths(scene);
    io::SweepProvenance provenance{scene.text, scene.material_text, config, mesh_file, io::file_hash(mesh_file),
                                   solver_options(scene), code_version};
    provenance.fibre_E = scene.fibre.E;
    provenance.fibre_nu = scene.fibre.nu;
    provenance.matrix_E = scene.matrix.E;
    provenance.matrix_nu = scene.matrix.nu;
    const double r = scene.geometry.fibre_radius, a = scene.geometry.cell_size;
    provenance.fibre_volume_fraction = std::numbers::pi * r * r / (a * a);
    {
      // Fail on an unwritable output before any work, not after hours of it.
      io::AtomicOutputs probe;
      probe.add(out);
    }
    const bool show = !quiet && ::isatty(2);
    const auto t0 = std::chrono::steady_clock::now();
    feti::ContactSolver solver(mesh_in.mesh, scene, threads);
    std::vector<sweep::PathResult> results;
    long computed = 0, total_steps = 0;
    for (const auto& spec : specs) total_steps += static_cast<long>(spec.loads.size());
    long done_steps = 0;
    for (const auto& spec : specs) {
      if (auto part = io::read_part(out, spec.index, provenance)) {
        results.push_back(std::move(*part));
        done_steps += static_cast<long>(spec.loads.size());
        continue;
      }
      const auto progress = [&](const sweep::PathSpec& p, int step, const sweep::Step& s) {
        if (!show) return;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        // Work done: finished paths' steps plus this path's share by load (bisection steps
        // for the fuse are not in the schedule, so counting steps would run ahead).
        const double finished = done_steps + p.loads.size() * std::abs(s.load / p.loads.back());
        const double eta = finished > 0 ? elapsed * (total_steps - finished) / finished : 0;
        std::fprintf(stderr, "\rdualcell-sweep: path %d/%zu (%s %g deg) step %d load %.4g broken %d  ETA %.0f s   ",
                     p.index + 1, specs.size(), p.sign > 0 ? "tension" : "compression", p.direction_deg, step + 1,
                     s.load, s.broken_bonds, eta);
      };
      results.push_back(sweep::run_path(solver, spec, scene.sweep.fuse_tolerance, progress));
      io::write_part(out, results.back(), provenance);
      done_steps += static_cast<long>(spec.loads.size());
      if (interrupt_after > 0 && ++computed >= interrupt_after) _exit(137);
    }
    io::write_sweep(out, results, provenance);
    if (show) std::fprintf(stderr, "\n");
    if (!quiet) {
      int fuses = 0, unconverged = 0;
      for (const auto& r : results) {
        fuses += r.fuse.has_value();
        for (const auto& s : r.steps) unconverged += !s.converged;
      }
      std::printf("dualcell-sweep: %zu paths -> %s (%d with a fuse, %d steps not converged), %.2f s\n", results.size(),
                  out.c_str(), fuses, unconverged,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  });
}
