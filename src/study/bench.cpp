// The performance study (`make -C pipelines bench`, dualcell-bench): numerical scalability, the
// linear-solve floor, sweep steps, memory, threads, and where the time goes. Ratios are measured
// within one run, so a busy machine shifts them less than absolute times.
//
//   numerical scalability  blocks 1×1 … 32×32 at degree 2, and degrees 1 … 8 on a 4×4 block:
//                          outer and inner iterations and applications of F, compression along
//                          x, no adhesion, symmetry boundary, E_f/E_m = 100
//   preconditioners        none, lumped, Dirichlet on the same cases: F and M⁻¹ applications,
//                          time, the fitted growth in H/h
//   floor                  one contact solve (setup + solve) against one CHOLMOD factorise and
//                          solve of the bonded problem as one body, same mesh, ~1e5 and ~1e6 DOF,
//                          with the time per phase
//   threads                the ~1e5 case on 1 and on all threads: speed-up, and the largest
//                          difference of λ and u between the two (the design gives 0)
//   sweep step             a further (warm-started, proportional) step against the first one
//   memory                 peak resident set per DOF of the contact solve at ~1e6 DOF
//   exact law              one cell's condensed law per evaluation (warm, cold) against its full
//                          solve; the condensation's seconds
//   dual operators         per subdomain of three cells: the cost model's seconds (implicit and
//                          explicit application, explicit setup) beside the measured ones, the
//                          break-even, and one solve with each operator
#include "study/bench.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "core/json.hpp"
#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "io/atomic_output.hpp"
#include "par/parallel.hpp"
#include "primal/one_body.hpp"

namespace dualcell::study {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

Scene block(int cells, int degree, Preconditioner preconditioner = Preconditioner::none, double strength = 0,
            Element element = Element::p1) {
  Scene s;
  s.geometry.element = element;
  s.geometry.cells = {cells, cells};
  s.geometry.cell_size = 1;
  s.geometry.fibre_radius = 0.3;
  s.geometry.degree = degree;
  s.fibre = {1e5, 0.2};
  s.matrix = {1e3, 0.4};
  s.interface = {strength, strength};
  s.load.boundary = Boundary::symmetry;
  s.solver.tolerance = 1e-8;
  s.solver.preconditioner = preconditioner;
  validate(s);
  return s;
}

std::string format(const char* pattern, auto... values) {
  char line[512];
  std::snprintf(line, sizeof line, pattern, values...);
  return line;
}

struct Run {
  int cells, degree, dofs;
  Element element;
  long rows;
  int threads;
  Preconditioner preconditioner;
  long outer, cg, expansion, proportioning, applications, preconditioner_applications;
  double setup_seconds, solve_seconds;
  feti::Timings phases;
  bool converged;
  Eigen::VectorXd lambda, u, f;
};

// progress: the solve's phases and QP iterations on stderr while it works (the big cases run
// for minutes); it reads a clock per F application and prints only when a line is due.
Run contact(int cells, int degree, int threads, Preconditioner preconditioner = Preconditioner::none,
            Element element = Element::p1, Progress* progress = nullptr) {
  const Scene s = block(cells, degree, preconditioner, 0, element);
  const mesh::Mesh m = mesh::build_mesh(s.geometry);
  const auto t0 = Clock::now();  // the mesh is an input of both solvers, timed in neither
  feti::ContactSolver solver(m, s, threads, feti::FetiSetup::default_min_dofs_per_thread, {}, progress);
  const double setup = since(t0);
  const auto t1 = Clock::now();
  feti::Solution r = solver.solve({-10, 0, 0}, solver.intact());
  const double solve = since(t1);
  const int used_threads = solver.setup().parallel() ? solver.setup().threads() : 1;
  return {cells,
          degree,
          m.dim_u(),
          element,
          r.n_rows,
          used_threads,
          preconditioner,
          r.counters.outer_iterations,
          r.counters.cg_steps,
          r.counters.expansion_steps,
          r.counters.proportioning_steps,
          r.counters.operator_applications,
          r.counters.preconditioner_applications,
          setup,
          solve,
          r.seconds,
          r.converged(),
          std::move(r.lambda),
          std::move(r.u),
          solver.setup().load({-10, 0, 0})};
}

// Least-squares slope of log(applications) against log(H/h), H/h = 4k intervals per cell edge.
double degree_exponent(const std::vector<Run>& runs) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const Run& r : runs) {
    const double x = std::log(4.0 * r.degree), y = std::log(static_cast<double>(r.applications));
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double n = static_cast<double>(runs.size());
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

const char* const run_header =
    "| cells | DOF | dim λ | outer | CG | expansion | proportioning | F applications | M⁻¹ applications | setup s | "
    "solve s |\n|---|---|---|---|---|---|---|---|---|---|---|\n";

std::string run_row(const Run& r) {
  return format("| %d×%d, k=%d | %d | %ld | %ld | %ld | %ld | %ld | %ld | %ld | %.3f | %.3f |\n", r.cells, r.cells,
                r.degree, r.dofs, r.rows, r.outer, r.cg, r.expansion, r.proportioning, r.applications,
                r.preconditioner_applications, r.setup_seconds, r.solve_seconds);
}

std::string run_json(const Run& r) {
  return JsonObject()
      .add("cells", std::to_string(r.cells * r.cells))
      .add("degree", std::to_string(r.degree))
      .add("dofs", std::to_string(r.dofs))
      .add_text("preconditioner", to_string(r.preconditioner))
      .add("operator_applications", std::to_string(r.applications))
      .add("preconditioner_applications", std::to_string(r.preconditioner_applications))
      .add("outer_iterations", std::to_string(r.outer))
      .add("seconds", json_number(r.setup_seconds + r.solve_seconds))
      .add("converged", r.converged ? "true" : "false")
      .str(6);
}

// Where the time of one solve goes, per phase (setup once per mesh and material; the rest per load).
std::string phase_row(const char* name, const Run& r) {
  const feti::Timings& t = r.phases;
  const double rest = t.qp - t.qp_F - t.qp_Q - t.qp_preconditioner;
  return format("| %s | %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n", name, r.threads, t.assembly,
                t.factorisation, t.dual_setup, t.qp_F, t.qp_Q, t.qp_preconditioner, rest, t.recovery);
}
const char* const phase_header =
    "| case | threads | assembly | factorisation | dual setup (B, G, GGᵀ) | QP: F | QP: Q (coarse) | QP: M⁻¹ | QP: "
    "other (vectors, d, λ₀) | recovery |\n|---|---|---|---|---|---|---|---|---|---|\n";

// The BLAS this process runs on: the file behind libblas.so.3 (or an OpenBLAS library) among
// the loaded objects, as /proc/self/maps lists them.
std::string loaded_blas() {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    if (path.find("libblas") != std::string::npos || path.find("openblas") != std::string::npos) {
      std::error_code ec;
      const auto real = std::filesystem::canonical(path, ec);
      return ec ? path : real.string();
    }
  }
  return "none loaded";
}

struct Floor {
  std::string md;
  std::vector<std::string> json;
  std::vector<Run> runs;
  double bytes_per_dof = 0;
};

// The floor: one contact solve (setup + solve, `threads` threads) against CHOLMOD's analyse,
// factorise and solve of the bonded problem as one body on the same mesh, for both element
// orders at ~1e5 and ~1e6 DOF.
Floor run_floor(int threads, bool quick) {
  Progress progress("dualcell-bench", true);
  struct Case {
    int cells, degree;
    Element element;
  };
  // p2 at degree k has the DOFs of p1 at 2k: 12×12 k=2 and 40×40 k=2 match the p1 rows' sizes.
  const std::vector<Case> cases =
      quick ? std::vector<Case>{{4, 2, Element::p1}, {4, 1, Element::p2}}
            : std::vector<Case>{{16, 3, Element::p1}, {12, 2, Element::p2}, {32, 5, Element::p1}, {40, 2, Element::p2}};
  const std::string blas = loaded_blas();
  Floor out;
  int largest_dofs = 0;
  std::ostringstream md;
  md << "## The floor: contact solve against one monolithic CHOLMOD solve\n\nThe contact solve (assembly, "
        "factorisations, dual setup, QP, recovery) on up to "
     << threads
     << " thread(s), no preconditioner; against CHOLMOD's analyse, factorise and solve of the assembled bonded "
        "problem as one body (supernodal, automatic ordering) on the BLAS this process loaded: "
     << blas
     << ". The mesh is timed in neither.\n\n| case | DOF | contact setup s | contact solve s | contact total s | "
        "CHOLMOD "
        "factorise+solve s | ratio | peak RSS bytes/DOF |\n|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto [n, k, element] = cases[i];
    Run r = contact(n, k, threads, Preconditioner::none, element, &progress);
    const long rss = par::peak_rss_bytes();
    const Scene bonded = block(n, k, Preconditioner::none, 1e12, element);
    const mesh::Mesh m = mesh::build_mesh(bonded.geometry);
    double cholesky = 0;  // same mesh and load (the load does not depend on the bonds)
    primal::solve_one_body(m, bonded, r.f, false, false, &cholesky);
    const double total = r.setup_seconds + r.solve_seconds;
    // The peak resident set is the process's: it says something about a row only when that row
    // is the largest problem so far.
    const bool largest = r.dofs >= largest_dofs;
    largest_dofs = std::max(largest_dofs, r.dofs);
    if (largest) out.bytes_per_dof = static_cast<double>(rss) / r.dofs;
    const std::string memory =
        largest ? format("%.0f", static_cast<double>(rss) / r.dofs) : std::string("(earlier rows)");
    md << format("| %d×%d, k=%d %s | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %s |\n", n, n, k, to_string(element),
                 r.dofs, r.setup_seconds, r.solve_seconds, total, cholesky, total / cholesky, memory.c_str());
    out.json.push_back(JsonObject()
                           .add_text("element", to_string(element))
                           .add("dofs", std::to_string(r.dofs))
                           .add("contact_seconds", json_number(total))
                           .add("cholesky_seconds", json_number(cholesky))
                           .add("contact_threads", std::to_string(r.threads))
                           .add_text("blas", blas)
                           .str(6));
    out.runs.push_back(std::move(r));
  }
  md << "\nTargets: ratio ≤ 3 at ~1e5 DOF and ≤ 2 at ~1e6 DOF. Peak RSS is the whole process's (it includes "
        "earlier rows); bytes/DOF at the largest case: "
     << out.bytes_per_dof << " (target ≤ 2048).\n";
  out.md = md.str();
  return out;
}

// Sweep step: a further proportional step against the first one (setup included).
void sweep_step(bool quick, int all, std::ostringstream& md, JsonObject& json) {
  std::fprintf(stderr, "dualcell-bench: sweep step\n");
  const auto [sn, sk] = quick ? std::pair<int, int>{4, 2} : std::pair<int, int>{16, 3};
  const Scene s = block(sn, sk);
  const auto t0 = Clock::now();
  const mesh::Mesh m = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(m, s, all);
  const feti::Solution first_step = solver.solve({-10, 0, 0}, solver.intact());
  const double first_seconds = since(t0);
  const Eigen::VectorXd lambda = 2 * first_step.lambda, multiplier = 2 * first_step.multiplier;
  const auto t1 = Clock::now();
  const feti::Solution second = solver.solve({-20, 0, 0}, solver.intact(), &lambda, &multiplier);
  const double second_seconds = since(t1);
  const double ratio = second_seconds / first_seconds;
  md << "## Sweep step\n\n"
     << sn << "×" << sn << " cells, degree " << sk << ": first step (setup + solve) " << first_seconds << " s, "
     << first_step.counters.operator_applications << " F applications; a further step " << second_seconds << " s, "
     << second.counters.operator_applications << " F applications: ratio " << ratio
     << " (target ≤ 0.1).\n\nThe thesis' cases beside the thesis' figures: thesis.md (make -C pipelines thesis).\n";
  json.add("sweep_step_ratio", json_number(ratio));
}

// The exact law of a cell against the full solve of that cell: one solve (dual setup and QP, the
// factors reused), the condensation, and the law's evaluations along a path of stresses turning
// about the sphere (warm: each from the last one's active set) and from the unloaded cell (cold),
// stress- and strain-driven.
void exact_law(std::ostringstream& md, JsonObject& json) {
  std::fprintf(stderr, "dualcell-bench: exact law\n");
  md << "## Exact law\n\nOne periodic cell, p2 at degree 4, E_f/E_m = 20, r = 0.4. Full solve: the dual setup and QP "
        "of one stress with the factors in place (best of 3). Per evaluation of the law: the mean over 400 stresses "
        "turning once about the sphere of directions, below any debond onset; warm (each from the last one's "
        "active set) and cold (each from the unloaded cell).\n\n| interface | rows | solve s | condensation s | "
        "law warm ms, stress-driven | warm ms, strain-driven | cold ms | warm / solve |\n"
        "|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> rows_json;
  for (const double strength : {0.0, 0.05}) {
    Scene s;
    s.geometry.element = Element::p2;
    s.geometry.cells = {1, 1};
    s.geometry.cell_size = 1;
    s.geometry.fibre_radius = 0.4;
    s.geometry.degree = 4;
    s.fibre = {20, 0.22};
    s.matrix = {1, 0.35};
    s.interface = {strength, strength};
    s.load.boundary = Boundary::periodic;
    s.solver.tolerance = 1e-8;
    validate(s);
    const mesh::Mesh m = mesh::build_mesh(s.geometry);
    feti::ContactSolver solver(m, s, 1);
    const Eigen::Vector3d sigma(0.01, -0.004, 0.003);
    double solve_seconds = 1e300;
    for (int repeat = 0; repeat < 3; ++repeat) {
      solver.forget_dual();
      const auto t0 = Clock::now();
      const feti::Solution one = solver.solve(sigma, solver.intact());
      solve_seconds = std::min(solve_seconds, since(t0));
    }
    const law::CondensedCell cell = feti::condense(solver.setup());
    law::CellEvaluator law(cell);
    // 400 stresses turning once about the sphere of (σxx, σyy, √2σxy), each of size 0.01, scaled
    // below half the debond onset along it with adhesion.
    std::vector<Eigen::Vector3d> path;
    for (int k = 0; k < 400; ++k) {
      const double t = 2 * std::numbers::pi * k / 400;
      const Eigen::Vector3d N(std::cos(t), std::sin(t) * std::cos(3 * t),
                              std::sin(t) * std::sin(3 * t) / std::sqrt(2.0));
      const double onset = law.onset(N);
      path.push_back(std::min(0.01, std::isfinite(onset) ? 0.5 * onset : 0.01) * N);
    }
    std::vector<Eigen::Vector3d> strains;
    for (const auto& p : path) {
      law::CellHistory fresh = law.unloaded();
      strains.push_back(law.at_stress(p, fresh).strain);
    }
    const auto mean_ms = [&](bool strain, bool warm) {
      law::CellHistory h = law.unloaded();
      const auto t0 = Clock::now();
      for (std::size_t k = 0; k < path.size(); ++k) {
        if (!warm) h = law.unloaded();
        const law::CellResponse r = strain ? law.at_strain(strains[k], h) : law.at_stress(path[k], h);
        if (!r.ok || r.broken > 0) throw std::runtime_error("exact law bench: " + r.message);
      }
      return 1e3 * since(t0) / static_cast<double>(path.size());
    };
    const double warm_stress = mean_ms(false, true), warm_strain = mean_ms(true, true), cold = mean_ms(false, false);
    const double ratio = 1e-3 * std::max(warm_stress, warm_strain) / solve_seconds;
    md << format("| %s | %d | %.4f | %.3f | %.4f | %.4f | %.3f | %.1e |\n",
                 strength > 0 ? "bonded (s_n = s_t = 0.05)" : "contact", cell.n_rows(), solve_seconds, cell.seconds,
                 warm_stress, warm_strain, cold, ratio);
    rows_json.push_back(JsonObject()
                            .add_text("interface", strength > 0 ? "bonded" : "contact")
                            .add("rows", std::to_string(cell.n_rows()))
                            .add("solve_seconds", json_number(solve_seconds))
                            .add("condensation_seconds", json_number(cell.seconds))
                            .add("warm_ms_stress", json_number(warm_stress))
                            .add("warm_ms_strain", json_number(warm_strain))
                            .add("cold_ms", json_number(cold))
                            .add("warm_over_solve", json_number(ratio))
                            .str(6));
  }
  md << "\nTarget: warm / solve ≤ 1e-3.\n";
  json.add("exact_law", json_list(rows_json));
}

}  // namespace

namespace {

void progress(const char* what);

// Median seconds of `repeat` calls of f (after one untimed call).
template <class F>
double median_seconds(int repeat, F&& f) {
  f();
  std::vector<double> t(static_cast<std::size_t>(repeat));
  for (double& x : t) {
    const auto t0 = Clock::now();
    f();
    x = since(t0);
  }
  std::nth_element(t.begin(), t.begin() + repeat / 2, t.end());
  return t[static_cast<std::size_t>(repeat / 2)];
}

struct OperatorCell {
  const char* name;
  Scene scene;
};

std::vector<OperatorCell> operator_cells() {
  std::vector<OperatorCell> cells;
  // The sweep's cell: glass/epoxy-like, v_f 0.5, periodic, p2 degree 4.
  Scene periodic = block(1, 4, Preconditioner::none, 0, Element::p2);
  periodic.geometry.fibre_radius = 0.3989;
  periodic.fibre = {72.0, 0.22};
  periodic.matrix = {3.5, 0.35};
  periodic.load.boundary = Boundary::periodic;
  cells.push_back({"periodic cell, p2 k=4", periodic});
  // The accuracy study's cell at the degree where p2 reaches 1e-4.
  Scene accuracy = block(1, 8, Preconditioner::none, 0, Element::p2);
  accuracy.fibre = {20.0, 0.22};
  accuracy.matrix = {1.0, 0.35};
  cells.push_back({"accuracy cell, p2 k=8", accuracy});
  // A block of the floor's kind: many small subdomains.
  cells.push_back({"4×4 block, p1 k=3", block(4, 3)});
  for (OperatorCell& c : cells) validate(c.scene);
  return cells;
}

// The cost model against the clock, per subdomain (docs/method.md §6a; feti/operator_cost.hpp),
// and one solve of each cell with each operator.
void dual_operators(std::ostringstream& md, JsonObject& json) {
  progress("dual operators");
  md << "\n## Dual operators: the cost model against the clock\n\nPer subdomain (for a block: its first "
        "matrix and fibre subdomain), seconds per application of the implicit operator (two sweeps with "
        "L) and of the explicit one (F_s x), and of forming the explicit one (the factorisation with the "
        "boundary last, K⁺(b, b), F_s): the model (feti/operator_cost.hpp) / measured (median of 50; the "
        "setup once). Break-even: the applications after which the explicit one has paid.\n\n"
        "| cell | subdomain | DOFs | rows | b | nnz(L) | implicit µs | explicit µs | setup ms | break-even |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> rows_json, solves_json;
  std::ostringstream solves;
  solves << "\nOne solve (σ̄ = (0.01, −0.005, 0), one thread; the setup once): seconds of the factorisations "
            "and explicit operators, of the QP, and F applications, per `[solver] dual_operator`.\n\n"
            "| cell | dual_operator | explicit subdomains | setup s | QP s | setup + QP s | F applications |\n"
            "|---|---|---|---|---|---|---|\n";
  for (const OperatorCell& cell : operator_cells()) {
    const mesh::Mesh m = mesh::build_mesh(cell.scene.geometry);
    Scene implicit = cell.scene, explicit_ = cell.scene;
    implicit.solver.dual_operator = DualOperator::implicit;
    explicit_.solver.dual_operator = DualOperator::explicit_;
    const feti::ContactSolver a(m, implicit);
    feti::ContactSolver b(m, explicit_);
    const feti::DualProblem& dual = b.problem(b.intact());
    bool matrix_done = false, fibre_done = false;
    for (const feti::FloatingSubdomain& sub : a.setup().subdomains()) {
      if (sub.is_macro || (sub.is_fibre ? fibre_done : matrix_done)) continue;
      (sub.is_fibre ? fibre_done : matrix_done) = true;
      const feti::FloatingSubdomain& e = b.setup().subdomains()[sub.index];
      const auto nb = static_cast<Eigen::Index>(e.boundary_dofs.size());
      const feti::OperatorCost model = feti::OperatorCost::of(*sub.K_plus, e.n_rows, nb);
      Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(sub.n_dofs, -1, 1), x(sub.n_dofs),
                      scratch(sub.K_plus->scratch_size());
      const double t_implicit = median_seconds(50, [&] { sub.K_plus->apply(y, x, scratch); });
      const Eigen::MatrixXd& F = *dual.locals()[sub.index].F;
      Eigen::VectorXd l = Eigen::VectorXd::LinSpaced(F.rows(), -1, 1), z(F.rows());
      const double t_explicit = median_seconds(50, [&] { z.noalias() = F * l; });
      const auto t0 = Clock::now();
      const linalg::FixingNodeInverse again(sub.K, sub.fixing_dofs,
                                            {linalg::FactorKind::simplicial, linalg::Ordering::amd}, e.boundary_dofs);
      const Eigen::MatrixXd K_bb = again.last_block_inverse();
      const double t_setup = since(t0);
      const double break_even = model.explicit_setup / std::max(model.implicit_apply - model.explicit_apply, 1e-300);
      md << format("| %s | %s %d | %d | %d | %ld | %ld | %.1f / %.1f | %.2f / %.2f | %.1f / %.1f | %.0f |\n", cell.name,
                   sub.is_fibre ? "fibre" : "matrix", sub.index, sub.n_dofs, e.n_rows, static_cast<long>(nb),
                   static_cast<long>(sub.K_plus->factor_nonzeros()), 1e6 * model.implicit_apply, 1e6 * t_implicit,
                   1e6 * model.explicit_apply, 1e6 * t_explicit, 1e3 * model.explicit_setup, 1e3 * t_setup, break_even);
      rows_json.push_back(JsonObject()
                              .add_text("cell", cell.name)
                              .add_text("subdomain", sub.is_fibre ? "fibre" : "matrix")
                              .add("dofs", std::to_string(sub.n_dofs))
                              .add("rows", std::to_string(e.n_rows))
                              .add("boundary_dofs", std::to_string(nb))
                              .add("model_implicit_seconds", json_number(model.implicit_apply))
                              .add("implicit_seconds", json_number(t_implicit))
                              .add("model_explicit_seconds", json_number(model.explicit_apply))
                              .add("explicit_seconds", json_number(t_explicit))
                              .add("model_setup_seconds", json_number(model.explicit_setup))
                              .add("setup_seconds", json_number(t_setup))
                              .add("break_even_applications", json_number(break_even))
                              .str(6));
    }
    const Eigen::Vector3d sigma(0.01, -0.005, 0);
    for (const DualOperator op : {DualOperator::implicit, DualOperator::automatic, DualOperator::explicit_}) {
      Scene s = cell.scene;
      s.solver.dual_operator = op;
      const auto t0 = Clock::now();
      feti::ContactSolver solver(m, s);
      const double setup = since(t0);
      const feti::Solution r = solver.solve(sigma, solver.intact());
      if (!r.converged()) throw std::runtime_error(std::string("dual operators bench: ") + r.qp.message);
      solves << format("| %s | %s | %d of %d | %.4f | %.4f | %.4f | %ld |\n", cell.name, to_string(op),
                       r.explicit_subdomains, r.subdomains, setup, r.seconds.qp, setup + r.seconds.qp,
                       r.counters.operator_applications);
      solves_json.push_back(JsonObject()
                                .add_text("cell", cell.name)
                                .add_text("dual_operator", to_string(op))
                                .add("explicit_subdomains", std::to_string(r.explicit_subdomains))
                                .add("setup_seconds", json_number(setup))
                                .add("qp_seconds", json_number(r.seconds.qp))
                                .add("operator_applications", std::to_string(r.counters.operator_applications))
                                .str(6));
    }
  }
  md << solves.str();
  json.add("dual_operators", json_list(rows_json));
  json.add("dual_operator_solves", json_list(solves_json));
}

}  // namespace

namespace {

// One section of the benchmark alone: <name>.md and <name>.json in the output folder, written
// together or not at all.
template <class Section>
std::string run_section_only(const BenchOptions& options, const std::string& name, const std::string& title,
                             Section&& section) {
  std::filesystem::create_directories(options.out_dir);
  io::AtomicOutputs outputs;
  const auto md_file = options.out_dir / (name + ".md"), json_file = options.out_dir / (name + ".json");
  outputs.add(md_file);
  outputs.add(json_file);
  std::ostringstream md;
  JsonObject json;
  md << title;
  section(md, json);
  outputs.write(md_file, md.str());
  outputs.write(json_file, json.str() + "\n");
  outputs.commit();
  return md.str();
}

}  // namespace

std::string run_operators_only(const BenchOptions& options) {
  return run_section_only(options, "operators", "# dualcell benchmark: dual operators\n", dual_operators);
}

std::string run_exact_law_only(const BenchOptions& options) {
  return run_section_only(options, "exact_law", "", exact_law);
}

std::string run_floor_only(const BenchOptions& options) {
  const int all = options.threads > 0 ? options.threads : omp_get_max_threads();
  std::filesystem::create_directories(options.out_dir);
  io::AtomicOutputs outputs;
  const auto md_file = options.out_dir / "floor.md", json_file = options.out_dir / "floor.json";
  outputs.add(md_file);
  outputs.add(json_file);
  const Floor floor = run_floor(all, options.quick);
  outputs.write(md_file, floor.md);
  outputs.write(json_file,
                JsonObject().add_text("blas", loaded_blas()).add("floor", json_list(floor.json)).str() + "\n");
  outputs.commit();
  return floor.md;
}

namespace {

// One line on stderr: which part of the benchmark runs.
void progress(const char* what) { std::fprintf(stderr, "dualcell-bench: %s\n", what); }

// The numerical scalability sections: block size and degree, for every preconditioner.
void scalability(bool quick, std::ostringstream& md, JsonObject& json) {
  std::vector<std::string> scalability_json, preconditioners_json;
  const std::vector<int> blocks = quick ? std::vector<int>{1, 2, 4} : std::vector<int>{1, 2, 4, 8, 16, 32};
  const int max_degree = quick ? 3 : 8;
  std::ostringstream summary_md;
  summary_md << "## Preconditioners: summary\n\n| preconditioner | F applications, largest block / 2×2 | growth "
                "exponent in H/h | solve s, largest block | solve s, 4×4 k="
             << max_degree << " |\n|---|---|---|---|---|\n";
  double exponent_none = 0, blocks_ratio_none = 0;
  for (Preconditioner p : {Preconditioner::none, Preconditioner::lumped, Preconditioner::dirichlet}) {
    progress((std::string("scalability, preconditioner ") + to_string(p)).c_str());
    md << "## Numerical scalability, preconditioner " << to_string(p) << ": block size (degree 2)\n\n" << run_header;
    long ops_2x2 = 0;
    Run largest{};
    for (int n : blocks) {
      Run r = contact(n, 2, 1, p);
      if (n == 2) ops_2x2 = r.applications;
      md << run_row(r);
      scalability_json.push_back(run_json(r));
      largest = std::move(r);
    }
    const double ratio = static_cast<double>(largest.applications) / ops_2x2;
    md << "\nF applications, " << largest.cells << "×" << largest.cells << " against 2×2: " << ratio
       << " (target ≤ 1.5)\n\n## Numerical scalability, preconditioner " << to_string(p) << ": degree (4×4 cells)\n\n"
       << run_header;
    std::vector<Run> by_degree;
    for (int k = 1; k <= max_degree; ++k) {
      by_degree.push_back(contact(4, k, 1, p));
      md << run_row(by_degree.back());
      scalability_json.push_back(run_json(by_degree.back()));
    }
    const double exponent = degree_exponent(by_degree);
    md << "\nFitted growth of F applications with H/h: exponent " << exponent << " (target ≤ 0.5)\n\n";
    summary_md << format("| %s | %.2f | %.2f | %.2f | %.2f |\n", to_string(p), ratio, exponent, largest.solve_seconds,
                         by_degree.back().solve_seconds);
    preconditioners_json.push_back(JsonObject()
                                       .add_text("preconditioner", to_string(p))
                                       .add("blocks_ratio_largest_to_2x2", json_number(ratio))
                                       .add("degree_exponent", json_number(exponent))
                                       .str(6));
    if (p == Preconditioner::none) exponent_none = exponent, blocks_ratio_none = ratio;
  }
  md << summary_md.str() << "\n";
  json.add("scalability", json_list(scalability_json))
      .add("degree_exponent", json_number(exponent_none))
      .add("blocks_ratio_largest_to_2x2", json_number(blocks_ratio_none))
      .add("preconditioners", json_list(preconditioners_json));
}

// Threads: the case tn × tn, degree tk on one thread against `all`; its phase rows close the
// floor's table.
void threads_section(int tn, int tk, int all, std::ostringstream& md, JsonObject& json) {
  progress("threads");
  const Run one = contact(tn, tk, 1);
  const Run many = contact(tn, tk, all);
  if (many.threads != all) progress("threads: the case is below the size from which threads spread");
  const double speedup = (one.setup_seconds + one.solve_seconds) / (many.setup_seconds + many.solve_seconds);
  const double lambda_difference =
      (one.lambda - many.lambda).lpNorm<Eigen::Infinity>() / std::max(one.lambda.lpNorm<Eigen::Infinity>(), 1e-300);
  const double u_difference =
      (one.u - many.u).lpNorm<Eigen::Infinity>() / std::max(one.u.lpNorm<Eigen::Infinity>(), 1e-300);
  md << phase_row(format("%d×%d, k=%d", tn, tn, tk).c_str(), one)
     << phase_row(format("%d×%d, k=%d", tn, tn, tk).c_str(), many) << "\n## Threads\n\n"
     << tn << "×" << tn << " cells, degree " << tk << ": setup + solve " << one.setup_seconds + one.solve_seconds
     << " s on 1 thread, " << many.setup_seconds + many.solve_seconds << " s on " << many.threads << ": speed-up "
     << speedup << " (setup " << one.setup_seconds / many.setup_seconds << ", solve "
     << one.solve_seconds / many.solve_seconds << "). Largest relative difference between the two: λ "
     << lambda_difference << ", u " << u_difference << " (target: ≤ 1e-14).\n\n";
  json.add("threads", JsonObject()
                          .add("count", std::to_string(many.threads))
                          .add("speedup", json_number(speedup))
                          .add("max_relative_difference_lambda", json_number(lambda_difference))
                          .add("max_relative_difference_u", json_number(u_difference))
                          .str(4));
}

// Progress on stderr costs nothing: the same solve with a live progress line and without,
// alternated three times, the fastest of each compared (docs: README, "Progress").
void progress_section(int tn, int tk, std::ostringstream& md, JsonObject& json) {
  progress("progress line");
  double with_line = 1e300, without_line = 1e300;
  long applications_with = 0, applications_without = 0;
  for (int repeat = 0; repeat < 3; ++repeat) {
    const Run plain = contact(tn, tk, 1);
    Progress live("dualcell-bench", true);
    const Run shown = contact(tn, tk, 1, Preconditioner::none, Element::p1, &live);
    live.finish();
    without_line = std::min(without_line, plain.solve_seconds + plain.setup_seconds);
    with_line = std::min(with_line, shown.solve_seconds + shown.setup_seconds);
    applications_without = plain.applications;
    applications_with = shown.applications;
  }
  const double progress_ratio = with_line / without_line;
  md << "## Progress\n\n"
     << tn << "×" << tn << " cells, degree " << tk << ", one thread, setup + solve, best of 3: " << with_line
     << " s with the progress line, " << without_line << " s without: ratio " << progress_ratio
     << " (target: within noise); F applications " << applications_with << " and " << applications_without
     << " (must be equal).\n\n";
  json.add("progress", JsonObject()
                           .add("ratio", json_number(progress_ratio))
                           .add("applications_with", std::to_string(applications_with))
                           .add("applications_without", std::to_string(applications_without))
                           .str(4));
}

}  // namespace

std::string run_bench(const BenchOptions& options) {
  const bool quick = options.quick;
  const int all = options.threads > 0 ? options.threads : omp_get_max_threads();
  std::filesystem::create_directories(options.out_dir);
  io::AtomicOutputs outputs;
  const auto md_file = options.out_dir / "bench.md", json_file = options.out_dir / "summary.json";
  outputs.add(md_file);
  outputs.add(json_file);
  std::ostringstream md;
  JsonObject json;
  md << "# dualcell benchmark\n\nCompression along x, no adhesion, symmetry boundary, E_f/E_m = 100, r = 0.3, "
        "tolerance 1e-8. Seconds are wall time on this machine in this run. Iteration counts do not depend on "
        "the thread count; the scalability rows run on one thread.\n\n";
  scalability(quick, md, json);
  // Floor and memory, on all threads.
  progress("floor");
  const Floor floor = run_floor(all, quick);
  const double bytes_per_dof = floor.bytes_per_dof;
  md << floor.md << "\n## Where the time goes (seconds per phase)\n\n" << phase_header;
  for (const Run& r : floor.runs)
    md << phase_row(format("%d×%d, k=%d %s", r.cells, r.cells, r.degree, to_string(r.element)).c_str(), r);
  const std::vector<std::string>& floor_json = floor.json;

  // The ~1e5 case for the threads and the progress line.
  const auto [tn, tk] = quick ? std::pair<int, int>{4, 2} : std::pair<int, int>{16, 3};
  json.add("bytes_per_dof", json_number(bytes_per_dof));
  json.add("floor", json_list(floor_json));
  threads_section(tn, tk, all, md, json);
  progress_section(tn, tk, md, json);
  sweep_step(quick, all, md, json);
  exact_law(md, json);
  dual_operators(md, json);
  outputs.write(md_file, md.str());
  outputs.write(json_file, json.str() + "\n");
  outputs.commit();
  return md.str();
}

}  // namespace dualcell::study
