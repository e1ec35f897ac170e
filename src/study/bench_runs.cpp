// The benchmark's block scenes, one timed contact solve and its table rows (bench_parts.hpp).
//                          break-even, and one solve with each operator
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
#include "study/bench_parts.hpp"

namespace dualcell::study::bench {

Scene block(int cells, int degree, Preconditioner preconditioner, double strength, Element element) {
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

Run contact(int cells, int degree, int threads, Preconditioner preconditioner, Element element, Progress* progress) {
  const Scene s = block(cells, degree, preconditioner, 0, element);
  const mesh::Mesh m = mesh::build_mesh(s.geometry);
  const auto t0 = Clock::now();  // the mesh is an input of both solvers, timed in neither
  feti::ContactSolver solver(m, s, threads, feti::FetiSetup::default_min_dofs_per_thread, {}, progress);
  const double setup = seconds_since(t0);
  const auto t1 = Clock::now();
  feti::Solution r = solver.solve({-10, 0, 0}, solver.intact());
  const double solve = seconds_since(t1);
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

double degree_exponent(const std::vector<Run>& runs) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const Run& r : runs) {
    const double x = std::log(4.0 * r.degree), y = std::log(static_cast<double>(r.applications));
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double n = static_cast<double>(runs.size());
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

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

std::string phase_row(const char* name, const Run& r) {
  const feti::Timings& t = r.phases;
  const double rest = t.qp - t.in_qp.F - t.in_qp.Q - t.in_qp.preconditioner;
  return format("| %s | %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n", name, r.threads, t.assembly,
                t.factorisation, t.dual_setup, t.in_qp.F, t.in_qp.Q, t.in_qp.preconditioner, rest, t.recovery);
}

void progress(const char* what) { std::fprintf(stderr, "dualcell-bench: %s\n", what); }

}  // namespace dualcell::study::bench
