#include "stage/sweep.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "feti/solver.hpp"
#include "io/atomic_output.hpp"
#include "io/sweep_file.hpp"
#include "stage/stage.hpp"
#include "sweep/sweep.hpp"

namespace dualcell::stage {

SweepSummary run_sweep(const SweepOptions& options) {
  using Clock = std::chrono::steady_clock;
  const SceneAndMesh in = load_scene_and_mesh("dualcell-sweep", options.scene_file, options.mesh_file);
  if (in.scene.load.boundary == Boundary::edges)
    throw InputError(in.scene.file.string() +
                     ": boundary = \"edges\" is a structure of resolved cells, not a cell to sweep: solve its load "
                     "steps with dualcell-solve (a sweep needs boundary = \"symmetry\", \"traction\" or \"periodic\")");
  const Scene& scene = in.scene;
  const std::vector<sweep::PathSpec> specs = sweep::plan_paths(scene);
  io::SweepHeader header;
  header.provenance.scene_text = scene.text;
  header.provenance.scene_file = options.scene_file;
  header.provenance.material_text = scene.material_text;
  header.provenance.mesh_file = in.mesh_file;
  header.provenance.mesh_hash = in.mesh_hash;
  header.provenance.solver_options = solver_options_text(scene);
  header.constituents = constituents(scene);
  {
    // Fail on an unwritable output before any work, not after hours of it.
    io::AtomicOutputs probe;
    probe.add(options.out);
  }
  const auto t0 = Clock::now();
  feti::ContactSolver solver(in.mesh, scene, options.threads);
  // Three unit solves with every bond lifted; the sweep's own onsets are checked against it in
  // the fit. Nothing to compute without adhesion.
  header.onset = solver.onset_surface();
  solver.forget_dual();
  std::vector<sweep::PathResult> results;
  SweepSummary summary;
  long computed = 0, total_steps = 0, done_steps = 0;
  for (const auto& spec : specs) total_steps += static_cast<long>(spec.loads.size());
  for (const auto& spec : specs) {
    if (auto part = io::read_part(options.out, spec.index, header)) {
      results.push_back(std::move(*part));
      done_steps += static_cast<long>(spec.loads.size());
      ++summary.resumed;
      continue;
    }
    const auto progress = [&](const sweep::PathSpec& p, int step, const sweep::Step& s) {
      if (!options.progress) return;
      const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
      // Work done: finished paths' steps plus this path's share by load (bisection steps for
      // the fuse are not in the schedule, so counting steps would run ahead).
      const double finished = done_steps + p.loads.size() * std::abs(s.load / p.loads.back());
      const double eta = finished > 0 ? elapsed * (total_steps - finished) / finished : 0;
      std::fprintf(stderr, "\rdualcell-sweep: path %d/%zu (%s %g deg) step %d load %.4g broken %ld  ETA %.0f s   ",
                   p.index + 1, specs.size(),
                   p.sphere     ? "sphere"
                   : p.sign > 0 ? "tension"
                                : "compression",
                   p.direction_deg, step + 1, s.load, s.broken_bonds, eta);
    };
    results.push_back(sweep::run_path(solver, spec, scene.sweep.fuse_tolerance, progress));
    io::write_part(options.out, results.back(), header);
    done_steps += static_cast<long>(spec.loads.size());
    if (options.interrupt_after > 0 && ++computed >= options.interrupt_after) _exit(137);
  }
  io::write_sweep(options.out, results, header);
  if (options.progress) std::fprintf(stderr, "\n");
  summary.paths = static_cast<int>(results.size());
  for (const auto& r : results) {
    summary.fuses += r.fuse.has_value();
    for (const auto& s : r.steps) summary.unconverged_steps += !s.converged;
  }
  summary.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return summary;
}

}  // namespace dualcell::stage
