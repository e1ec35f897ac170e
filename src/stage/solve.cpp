#include "stage/solve.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"
#include "feti/constraints.hpp"
#include "io/atomic_output.hpp"
#include "io/solution_file.hpp"
#include "par/parallel.hpp"
#include "primal/antiplane.hpp"
#include "stage/stage.hpp"
#include "sweep/sweep.hpp"

namespace dualcell::stage {

Eigen::Vector3d parse_stress(const std::string& text) {
  std::stringstream in(text);
  Eigen::Vector3d sigma;
  std::string item;
  int i = 0;
  while (std::getline(in, item, ',')) {
    if (i >= 3) break;
    try {
      std::size_t used = 0;
      sigma(i) = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(sigma(i))) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError("--stress " + text + ": '" + item + "' is not a finite number");
    }
    ++i;
  }
  if (i != 3 || std::getline(in, item)) throw InputError("--stress " + text + ": expected three numbers sxx,syy,sxy");
  return sigma;
}

namespace {

// The load steps of a block with boundary = "edges": a sweep::LoadWalk along the load factor
// (bonds carried from step to step, breaks irreversible, warm starts scaled); one line per step
// on `progress`. `work` gets every step's QP seconds and exchanges added (the last step's
// solution has only its own).
feti::Solution solve_steps(feti::ContactSolver& solver, const Scene& scene, feti::BondState bonds, io::LoadSteps& steps,
                           feti::Timings& work, Progress& progress) {
  const EdgeLoads& loads = scene.load.edge_loads;
  const int watch = feti::node_at(solver.setup().mesh(), loads.watch, loads.watch_where, "[output] watch");
  steps.first_break_factor = solver.debond_onset(Eigen::Vector3d(1, 0, 0));
  const feti::BondState intact = solver.intact();
  sweep::LoadWalk walk(solver, MacroState::stress(Eigen::Vector3d(1, 0, 0)).hold(MacroState::dT, scene.load.delta_T),
                       std::move(bonds));
  feti::Solution s;
  for (std::size_t k = 0; k < loads.factors.size(); ++k) {
    const double t = loads.factors[k];
    s = walk.solve(t);
    walk.accept(t, s);
    work.add_qp(s.seconds);
    const long broken = sweep::count_broken(intact, s.bonds);
    steps.factor.push_back(t);
    steps.watch_displacement.insert(steps.watch_displacement.end(), {s.u(2 * watch), s.u(2 * watch + 1)});
    steps.newly_broken.push_back(s.newly_broken);
    steps.broken.push_back(broken);
    steps.converged.push_back(s.converged() ? 1 : 0);
    steps.operator_applications.push_back(s.counters.operator_applications);
    char line[160];
    std::snprintf(line, sizeof line, "step %zu/%zu, factor %g: %s, %ld F applications, %ld bonds broken", k + 1,
                  loads.factors.size(), t, s.converged() ? "converged" : "NOT converged",
                  s.counters.operator_applications, broken);
    progress.message(line);
  }
  return s;
}

// The load of one solve into `outcome.solution` (or `outcome.steps`): with the scene's ΔT the
// cool-down first at zero macro stress, from `bonds`, then the load from its bond state with ΔT
// held (docs/theory/model.md §1a); `work` gets every solve's QP time.
void solve_load(feti::ContactSolver& solver, const Scene& scene, const SolveOptions& options,
                const Eigen::Vector3d& sigma, feti::BondState bonds, SolveOutcome& outcome, feti::Timings& work,
                Progress& progress) {
  const bool edges = scene.load.boundary == Boundary::edges;
  const double delta_T = scene.load.delta_T;
  if (delta_T != 0) {
    // The cure's cool-down first, at zero macro stress (docs/theory/model.md §1a).
    progress.message("cool-down, delta_T " + shortest(delta_T));
    const feti::Solution cool =
        solver.solve(MacroState::stress(Eigen::Vector3d::Zero()).hold(MacroState::dT, delta_T), bonds);
    outcome.cool_down_broken = sweep::count_broken(bonds, cool.bonds);
    work.add_qp(cool.seconds);
    bonds = cool.bonds;
    // A cool-down that did not converge is the answer, written and marked (exit 4), not a start.
    if (!cool.converged()) {
      outcome.solution = cool;
      progress.message("the cool-down did not converge: no load applied");
      return;
    }
  }
  if (edges) {
    outcome.steps.emplace();
    outcome.solution = solve_steps(solver, scene, bonds, *outcome.steps, work, progress);
  } else {
    outcome.solution = solver.solve(
        MacroState::stress(sigma).hold(MacroState::zz, options.eps33).hold(MacroState::dT, delta_T), bonds);
    work.add_qp(outcome.solution.seconds);
  }
}

// This rank's entry of the rank table; `t` holds the QP work of the whole run (every load step's).
io::RankEntry rank_entry(const feti::ContactSolver& solver, const feti::Timings& t) {
  const feti::FetiSetup& setup = solver.setup();
  io::RankEntry e;
  e.first_subdomain = setup.owned_begin();
  e.subdomains = setup.owned_end() - setup.owned_begin();
  e.dofs = setup.owned_dofs();
  e.subdomain_bytes = static_cast<std::int64_t>(setup.owned_bytes());
  e.peak_rss_bytes = static_cast<std::int64_t>(par::peak_rss_bytes());
  e.seconds_setup = setup.seconds_assembly + setup.seconds_factorisation + setup.seconds_explicit;
  e.seconds_apply = t.in_qp.F + t.in_qp.preconditioner - t.in_qp.communication;
  e.seconds_communication = t.in_qp.communication;
  e.exchanges = t.in_qp.exchanges;
  e.bytes_received = static_cast<std::int64_t>(t.in_qp.bytes_received);
  return e;
}

}  // namespace

SolveOutcome run_solve(const SolveOptions& options) {
  // Every rank reads the scene, the mesh and the bond state; an input error is agreed on before
  // any work, so that every rank stops with the same one message.
  std::optional<SceneAndMesh> loaded;
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();
  std::optional<feti::BondState> bonds_read;
  std::string problem;
  try {
    // Every output path checked before any work (not after it), against every input it could destroy.
    const std::vector<std::filesystem::path> outputs{options.out, io::xdmf_beside(options.out)};
    std::vector<std::filesystem::path> inputs{options.scene_file, options.mesh_file, options.bonds_file};
    for (const auto& out : outputs) io::check_output_path(out, inputs);
    loaded.emplace(load_scene_and_mesh("dualcell-solve", options.scene_file, options.mesh_file));
    const Scene& scene = loaded->scene;
    inputs.push_back(scene.material_file);
    const bool edges = scene.load.boundary == Boundary::edges;
    if (edges && !options.stress_text.empty())
      throw InputError("--stress " + options.stress_text + ": " + scene.file.string() +
                       " has boundary = \"edges\": its loads and steps are in the scene; leave --stress out");
    if (!edges && options.stress_text.empty())
      throw InputError(scene.file.string() + ": boundary = \"" + to_string(scene.load.boundary) +
                       "\" needs --stress sxx,syy,sxy");
    if (edges && options.eps33 != 0)
      throw InputError("--eps33 " + formatted("%g", options.eps33) + ": " + scene.file.string() +
                       " has boundary = \"edges\", a structure in plane strain; leave --eps33 out");
    if (options.longitudinal_shear && scene.load.boundary != Boundary::periodic)
      throw InputError("--longitudinal-shear: " + scene.file.string() + " has boundary = \"" +
                       to_string(scene.load.boundary) + "\"; the longitudinal shear of a cell needs \"periodic\"");
    if (options.onset && (edges || !scene.interface.has_adhesion() || options.eps33 != 0))
      throw InputError(std::string("--onset: ") +
                       (edges ? "boundary = \"edges\" prints its first break by itself"
                        : options.eps33 != 0
                            ? "not with --eps33 (the onset is along a stress, with the scene's delta_T held)"
                            : scene.file.string() + " has no adhesion: nothing to break"));
    if (edges) feti::check_positions(loaded->mesh, scene.load.edge_loads);
    if (!edges) sigma = parse_stress(options.stress_text);
    check_load_strain(scene, sigma.lpNorm<Eigen::Infinity>(), "--stress " + options.stress_text);
    if (scene.load.boundary == Boundary::symmetry && sigma(2) != 0)
      throw InputError("--stress " + options.stress_text +
                       ": the symmetry boundary carries only sxx and syy (sxy must be 0); use boundary = "
                       "\"traction\" or \"periodic\" for shear");
    if (!options.bonds_file.empty()) bonds_read = io::read_bonds(options.bonds_file, loaded->mesh, loaded->mesh_hash);
    if (par::rank() == 0) io::check_outputs(outputs, inputs);
  } catch (const InputError& e) {
    problem = e.what();
  }
  par::agree_on_error(problem);
  SceneAndMesh& in = *loaded;
  // The phases and the QP's outer iterations on stderr while it works (rank 0 only).
  Progress progress("dualcell-solve", options.progress && par::rank() == 0);
  feti::ContactSolver solver(in.mesh, in.scene, options.threads, feti::FetiSetup::default_min_dofs_per_thread,
                             par::Group::world(), &progress);
  const feti::BondState bonds = bonds_read ? *bonds_read : solver.intact();
  SolveOutcome outcome;
  feti::Timings work;
  solve_load(solver, in.scene, options, sigma, bonds, outcome, work, progress);
  if (options.onset) {
    outcome.onset = solver.debond_onset(sigma);
    outcome.onset_note = solver.onset_note();
  }
  outcome.ranks = io::unpack_rank_table(solver.setup().group().gather(io::pack(rank_entry(solver, work))));
  std::optional<primal::LongitudinalShear> shear;
  if (options.longitudinal_shear && par::rank() == 0) {
    std::vector<char> bonded(in.mesh.interface_pairs.size(), 0);
    if (in.scene.interface.has_adhesion())
      for (std::size_t p = 0; p < bonded.size(); ++p) bonded[p] = outcome.solution.bonds[p] != 0;
    shear = primal::longitudinal_shear(in.mesh, in.scene.fibre, in.scene.matrix, bonded);
    outcome.longitudinal_shear = shear->G;
  }
  if (par::rank() == 0) {
    Provenance provenance;
    provenance.mesh_file = in.mesh_file;
    provenance.mesh_hash = in.mesh_hash;
    const feti::SolutionFields fields = feti::solution_fields(in.mesh, in.scene, outcome.solution.u,
                                                              {outcome.solution.eps33, outcome.solution.delta_T});
    io::write_solution(options.out, in.mesh, in.scene, outcome.solution, fields, provenance,
                       outcome.steps ? &*outcome.steps : nullptr, &outcome.ranks, shear ? &*shear : nullptr);
    outcome.written = true;
  }
  outcome.dim_u = in.mesh.dim_u();
  outcome.threads_used = solver.setup().parallel() ? solver.setup().threads() : 1;
  outcome.scene = std::move(in.scene);
  return outcome;
}

void print_solve_summary(const SolveOptions& options, const SolveOutcome& outcome) {
  const feti::Solution& s = outcome.solution;
  const Scene& scene = outcome.scene;
  const Eigen::Vector3d& sigma = s.sigma;
  long broken = 0;
  for (auto b : s.bonds) broken += b == 0;
  if (outcome.steps) {
    const io::LoadSteps& st = *outcome.steps;
    std::printf("dualcell-solve: %s + %s, %zu load step(s) on the edges -> %s\n", options.scene_file.c_str(),
                options.mesh_file.c_str(), st.factor.size(), options.out.c_str());
    std::printf("  first bond break at load factor %.6g\n", st.first_break_factor);
    std::printf("  %6s %12s %14s %14s %8s %8s %10s\n", "step", "factor", "watch ux", "watch uy", "broken", "total",
                "F appl.");
    for (std::size_t k = 0; k < st.factor.size(); ++k)
      std::printf("  %6zu %12.6g %14.6e %14.6e %8lld %8lld %10lld%s\n", k + 1, st.factor[k],
                  st.watch_displacement[2 * k], st.watch_displacement[2 * k + 1],
                  static_cast<long long>(st.newly_broken[k]), static_cast<long long>(st.broken[k]),
                  static_cast<long long>(st.operator_applications[k]), st.converged[k] ? "" : "  NOT converged");
  } else {
    std::printf("dualcell-solve: %s + %s, stress (%g, %g, %g) -> %s\n", options.scene_file.c_str(),
                options.mesh_file.c_str(), sigma(0), sigma(1), sigma(2), options.out.c_str());
  }
  std::printf("  boundary %s, adhesion %s, dim u %d, dim lambda %ld\n", to_string(scene.load.boundary),
              scene.interface.has_adhesion() ? "yes" : "no", outcome.dim_u, s.n_rows);
  std::printf("  dual operator %s: explicit in %d of %d subdomains\n", to_string(scene.solver.dual_operator),
              s.explicit_subdomains, s.subdomains);
  std::printf(
      "  status %s: %ld outer iterations, %ld operator applications (%ld CG, %ld expansion, %ld proportioning)\n",
      qp::to_string(s.qp.status), s.counters.outer_iterations, s.counters.operator_applications, s.counters.cg_steps,
      s.counters.expansion_steps, s.counters.proportioning_steps);
  if (s.tightenings > 0)
    std::printf("  the primal check asked for more accuracy: dual tolerance tightened %ld time(s) to %.0e\n",
                s.tightenings, s.qp_tolerance);
  if (outcome.cool_down_broken)
    std::printf("  cool-down     delta_T %g K at zero macro stress, solved first: %ld bonds broken by it\n", s.delta_T,
                *outcome.cool_down_broken);
  if (outcome.onset)
    std::printf("  debond onset  s* = %.9g along this stress (%s)\n", *outcome.onset,
                !outcome.onset_note.empty() ? outcome.onset_note.c_str()
                : s.delta_T != 0            ? "first break of the intact interface at s* x stress, from the cool-down"
                                            : "first break of the intact interface at s* x stress");
  if (scene.interface.has_adhesion())
    std::printf("  bonds: %ld debond rounds, %ld broken now, %ld broken in all of %zu\n", s.debond_rounds,
                s.newly_broken, broken, s.bonds.size());
  if (!outcome.steps) {
    std::printf("  macro strain  exx %.6e  eyy %.6e  exy %.6e\n", s.strain(0), s.strain(1), s.strain(2));
    std::printf("  Hill-Mandel   <s> - s_applied = (%.2e, %.2e, %.2e)\n", s.average_stress(0) - sigma(0),
                s.average_stress(1) - sigma(1), s.average_stress(2) - sigma(2));
    if (s.eps33 != 0 || s.delta_T != 0)
      std::printf("  longitudinal  e33 %.6e (given), <szz> %.6e\n", s.eps33, s.average_stress_zz);
  }
  if (outcome.longitudinal_shear) {
    const Eigen::Matrix2d& G = *outcome.longitudinal_shear;
    std::printf("  longitudinal shear moduli (bonds as this load left them): Gxz %.6g  Gyz %.6g  Gxz,yz %.3g\n",
                G(0, 0), G(1, 1), G(0, 1));
  }
  std::printf(
      "  KKT: projected gradient %.2e (rel), |G l - e| %.2e (rel), bound violation %.2e,\n"
      "       complementarity %.2e, penetration %.2e, glue jump %.2e, equilibrium %.2e (rel)\n",
      s.kkt.relative_projected_gradient, s.kkt.relative_equality_residual, s.kkt.bound_violation, s.kkt.complementarity,
      s.kkt.max_penetration, s.kkt.max_glue_jump, s.kkt.relative_equilibrium);
  std::printf(
      "  seconds: assembly %.3f, factorisation %.3f, explicit F_s %.3f, dual setup %.3f, QP %.3f (F %.3f, Q %.3f, "
      "M^-1 %.3f), recovery %.3f; %d thread(s)\n",
      s.seconds.assembly, s.seconds.factorisation, s.seconds.explicit_operators, s.seconds.dual_setup, s.seconds.qp,
      s.seconds.in_qp.F, s.seconds.in_qp.Q, s.seconds.in_qp.preconditioner, s.seconds.recovery, outcome.threads_used);
  if (scene.solver.preconditioner != Preconditioner::none)
    std::printf("  preconditioner %s: %ld applications\n", to_string(scene.solver.preconditioner),
                s.counters.preconditioner_applications);
  const io::RankTable& r = outcome.ranks;
  if (r.size() > 1) {
    std::printf(
        "  %zu ranks: subdomain data, peak memory, and seconds (setup; applying F and M^-1: own share, "
        "exchanges)\n",
        r.size());
    std::printf("  %6s %8s %10s %10s %9s %9s %9s %9s %10s\n", "rank", "subdom.", "dofs", "data MiB", "peak MiB",
                "setup s", "apply s", "comm. s", "recv. MiB");
    for (std::size_t p = 0; p < r.size(); ++p)
      std::printf("  %6zu %8lld %10lld %10.1f %9.1f %9.3f %9.3f %9.3f %10.1f\n", p,
                  static_cast<long long>(r[p].subdomains), static_cast<long long>(r[p].dofs),
                  r[p].subdomain_bytes / 1048576.0, r[p].peak_rss_bytes / 1048576.0, r[p].seconds_setup,
                  r[p].seconds_apply, r[p].seconds_communication, r[p].bytes_received / 1048576.0);
  }
}

}  // namespace dualcell::stage
