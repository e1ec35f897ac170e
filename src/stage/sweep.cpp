#include "stage/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/text.hpp"
#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "io/atomic_output.hpp"
#include "io/sweep_file.hpp"
#include "law/onset.hpp"
#include "par/parallel.hpp"
#include "stage/stage.hpp"
#include "sweep/checks.hpp"
#include "sweep/sweep.hpp"

namespace dualcell::stage {

namespace {

using Clock = std::chrono::steady_clock;

// "tension 90 deg", "compression 45 deg", "sphere" (a sphere path is a general stress direction).
std::string path_label(const sweep::PathSpec& p) {
  if (p.sphere) return "sphere";
  char text[64];
  std::snprintf(text, sizeof text, "%s %g deg", p.sign > 0 ? "tension" : "compression", p.direction_deg);
  return text;
}

// Every rank reads the scene and the mesh (nothing of a rank's data is shared). An input error
// is agreed on before any work, so that every rank stops with the same one message instead of
// some ranks waiting for the others; the output is checked before any work, not after hours.
SceneAndMesh load_inputs(const SweepOptions& options) {
  std::optional<SceneAndMesh> loaded;
  std::string problem;
  try {
    std::vector<std::filesystem::path> inputs{options.scene_file, options.mesh_file};
    io::check_output_path(options.out, inputs);
    loaded.emplace(load_scene_and_mesh("dualcell-sweep", options.scene_file, options.mesh_file));
    inputs.push_back(loaded->scene.material_file);
    if (loaded->scene.load.boundary == Boundary::edges)
      throw InputError(loaded->scene.file.string() +
                       ": boundary = \"edges\" is a structure of resolved cells, not a cell to sweep: solve its load "
                       "steps with dualcell-solve (a sweep needs boundary = \"symmetry\", \"traction\" or "
                       "\"periodic\")");
    // Every path's onset from the cool-down is affine only where every interface row has a
    // strength; shear-only adhesion keeps the normal rows contact rows (docs/theory/model.md §1a).
    const Scene& scene = loaded->scene;
    if (scene.load.delta_T != 0 && scene.interface.has_adhesion() && scene.interface.normal_strength == 0)
      throw InputError(
          scene.file.string() + ": [load] delta_T = " + shortest(scene.load.delta_T) +
          " with adhesion in shear only ([interface] normal_strength = 0): the onset from the cool-down is "
          "not affine there; give normal_strength too, or sweep without delta_T");
    if (par::rank() == 0) io::check_outputs({options.out}, inputs);
  } catch (const InputError& e) {
    problem = e.what();
  }
  par::agree_on_error(problem);
  return std::move(*loaded);
}

// What sweep.h5 records besides its paths (the onset surface is added once the solver exists).
sweep::SweepHeader header_of(const SweepOptions& options, const SceneAndMesh& in) {
  sweep::SweepHeader header;
  header.provenance.scene_text = in.scene.text;
  header.provenance.scene_file = options.scene_file;
  header.provenance.material_text = in.scene.material_text;
  header.provenance.mesh_file = in.mesh_file;
  header.provenance.mesh_hash = in.mesh_hash;
  header.provenance.solver_options = solver_options_text(in.scene);
  header.constituents = constituents(in.scene);
  header.qp_tolerance = in.scene.solver.tolerance;
  header.delta_T = in.scene.load.delta_T;
  return header;
}

// Rank 0 gathers every path, its own and the others' from the journal, in plan order.
std::vector<sweep::PathResult> collect_paths(const SweepOptions& options, const std::vector<sweep::PathSpec>& specs,
                                             std::map<int, sweep::PathResult>& computed_here,
                                             const sweep::SweepHeader& header) {
  std::vector<sweep::PathResult> results;
  for (const auto& spec : specs) {
    if (auto mine = computed_here.find(spec.index); mine != computed_here.end()) {
      results.push_back(std::move(mine->second));
    } else if (auto part = io::read_part(options.out, spec.index, header)) {
      results.push_back(std::move(*part));
    } else {
      throw std::runtime_error("path " + std::to_string(spec.index) + " is missing from the journal of " + options.out +
                               " after every rank finished");
    }
  }
  return results;
}

// The progress line of a step: the path, step, load, broken bonds and the time left. Work done:
// finished paths' steps plus this path's share by load (bisection steps for the fuse are not in
// the schedule, so counting steps would run ahead).
std::string step_progress(const sweep::PathSpec& p, std::size_t n_paths, int step, const sweep::Step& s,
                          long done_steps, long total_steps, double elapsed) {
  const double finished = done_steps + p.loads.size() * std::abs(s.load / p.loads.back());
  const double left = finished > 0 ? elapsed * (total_steps - finished) / finished : 0;
  char text[200];
  std::snprintf(text, sizeof text, "path %d/%zu (%s) step %d load %.4g broken %ld, %s, ~%s left", p.index + 1, n_paths,
                path_label(p).c_str(), step + 1, s.load, s.broken_bonds, seconds_text(elapsed).c_str(),
                seconds_text(left).c_str());
  return text;
}

// What the summary says of the written sweep: paths, fuses, unconverged steps, the exact law.
void summarise(SweepSummary& summary, const std::vector<sweep::PathResult>& results, const sweep::SweepHeader& header) {
  summary.written = true;
  summary.paths = static_cast<int>(results.size());
  for (const auto& r : results) {
    summary.fuses += r.fuse.has_value();
    for (const auto& st : r.steps) summary.unconverged_steps += !st.converged;
  }
  if (header.cell) {
    summary.cell_rows = header.cell->n_rows();
    summary.cell_bytes = static_cast<double>(header.cell->bytes());
    summary.cell_seconds = header.cell->seconds;
  }
  summary.cell_note = header.cell_note;
  if (header.cell_basis) {
    summary.basis_rows = header.cell_basis->n_rows();
    summary.basis_seconds = header.cell_basis->seconds;
  }
}

// Whether the fit needs the cell on a basis of its own solutions: a cell without adhesion whose
// exact law is missing or too large to sample, with enough sphere paths to fit the small cell to
// and to hold out its check.
bool needs_basis(const Scene& scene, const sweep::SweepHeader& header, const SweepOptions& options) {
  return !scene.interface.has_adhesion() && scene.load.delta_T == 0 && scene.sweep.sphere >= 2 * fit::min_held_out &&
         (!header.cell || header.cell->n_rows() > options.sampled_rows);
}

}  // namespace

SweepSummary run_sweep(const SweepOptions& options) {
  const SceneAndMesh in = load_inputs(options);
  const Scene& scene = in.scene;
  const std::vector<sweep::PathSpec> specs = sweep::plan_paths(scene);
  sweep::SweepHeader header = header_of(options, in);
  const auto t0 = Clock::now();
  // Groups of ranks_per_path consecutive ranks share one solver; the group's first rank (its
  // leader) takes the paths, journals them and reports, the others follow it.
  const int ranks = par::size();
  const par::Group group = par::Group::world().split(par::rank() / std::max(1, options.ranks_per_path));
  const bool leader = group.rank() == 0;
  // The QPs this group will solve, for the choice of dual operator: its share of the paths'
  // loads (bisections of a fuse and debond rounds come on top; the estimate errs low).
  double loads = 0;
  for (const sweep::PathSpec& spec : specs) loads += static_cast<double>(spec.loads.size());
  const int groups = std::max(1, ranks / std::max(1, options.ranks_per_path));
  feti::ContactSolver solver(in.mesh, scene, options.threads, feti::FetiSetup::default_min_dofs_per_thread, group,
                             nullptr, std::max(1.0, loads / groups));
  // Three unit solves with every bond lifted; the sweep's own onsets are checked against it in
  // the fit. Nothing to compute without adhesion. Every rank has it (the journal's header).
  header.onset = solver.onset_surface();
  // The exact law, from the same factorisation: built by the group of rank 0, which writes sweep.h5.
  if (par::rank() < std::max(1, options.ranks_per_path)) {
    if (scene.load.delta_T != 0) {
      header.cell_note =
          "a temperature change ([load] delta_T): the fit does not take such a sweep yet (the compact forms' apex "
          "is off the origin), so no exact law is kept with it; the exact law of a sweep at delta_T = 0 carries any "
          "temperature change (dualcell-law --delta-T)";
    } else {
      try {
        header.cell = feti::condense(solver.setup());
      } catch (const InputError& e) {
        header.cell_note = e.what();
      }
    }
    if (header.cell && header.cell->longitudinal == 1)
      header.longitudinal_points = sweep::longitudinal_points(solver, scene, specs, header.onset);
    if (header.cell && header.cell->shear == 2) header.shear_points = sweep::shear_points(in.mesh, scene);
    header.expansion = solver.bonded_expansion();
    if (needs_basis(scene, header, options))
      sweep::build_basis(solver, scene, header, options.progress && par::rank() == 0);
  }

  // Paths are handed out one at a time to whichever rank asks next (their costs differ: a fuse
  // bracket is bisected), each computed path journaled at once by the rank that computed it.
  // Each path starts from a cleared solver (run_path), so its numbers do not depend on which
  // rank solved it or what that rank solved before: any P gives the serial sweep.h5.
  SweepSummary summary;
  std::map<int, sweep::PathResult> computed_here;
  long computed = 0, total_steps = 0, done_steps = 0;
  for (const auto& spec : specs) total_steps += static_cast<long>(spec.loads.size());
  // One line with the path, step, load, broken bonds and the time left (alone: under several
  // ranks each rank reports its finished paths instead).
  Progress progress("dualcell-sweep", options.progress && ranks == 1);
  {
    par::SharedCounter next_path;
    const auto next = [&] { return group.broadcast(leader ? next_path.next() : 0, 0); };
    for (long i = next(); i < static_cast<long>(specs.size()); i = next()) {
      const sweep::PathSpec& spec = specs[i];
      // Whether the journal has the path: the leader's view for the whole group, so that no
      // rank of it starts a solve the others skip.
      if (group.broadcast(leader && io::read_part(options.out, spec.index, header) ? 1 : 0, 0)) {
        if (leader) ++summary.resumed;
        done_steps += static_cast<long>(spec.loads.size());
        continue;
      }
      const auto on_step = [&](const sweep::PathSpec& p, int step, const sweep::Step& s) {
        if (par::rank() == 0) next_path.serve();  // after every step: the others' next path
        progress.update(
            [&] { return step_progress(p, specs.size(), step, s, done_steps, total_steps, progress.seconds()); });
      };
      sweep::PathResult result = sweep::run_path(solver, spec, scene.sweep.fuse_tolerance, on_step);
      if (!leader) continue;
      io::write_part(options.out, result, header);
      if (options.progress && ranks > 1)
        std::fprintf(stderr, "dualcell-sweep: rank %d/%d: path %d/%zu (%s) done, %.0f s\n", par::rank(), ranks,
                     spec.index + 1, specs.size(), path_label(spec).c_str(), seconds_since(t0));
      done_steps += static_cast<long>(spec.loads.size());
      if (par::rank() == 0) computed_here.emplace(spec.index, std::move(result));
      // The test hook kills one rank only, the last group's leader (the only rank without MPI),
      // with kill -9's own signal: no destructor, no flush, no MPI_Finalize.
      const int last_leader = (ranks - 1) / std::max(1, options.ranks_per_path) * std::max(1, options.ranks_per_path);
      if (options.interrupt_after > 0 && par::rank() == last_leader && ++computed >= options.interrupt_after)
        std::raise(SIGKILL);
    }
  }
  progress.finish();
  summary.resumed = static_cast<int>(par::sum(summary.resumed));
  // Every path is journaled now; rank 0 alone writes sweep.h5, from its own paths and the
  // journal of the others.
  par::barrier();
  if (par::rank() != 0) return summary;
  const std::vector<sweep::PathResult> results = collect_paths(options, specs, computed_here, header);
  io::write_sweep(options.out, results, header);
  summarise(summary, results, header);
  summary.seconds = seconds_since(t0);
  summary.dual_operator = to_string(scene.solver.dual_operator);
  summary.subdomains = solver.setup().n_stiff_subdomains();
  summary.explicit_subdomains = solver.setup().explicit_subdomains();
  return summary;
}

}  // namespace dualcell::stage
