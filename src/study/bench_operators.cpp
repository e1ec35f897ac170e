// The benchmark's dual-operator section: the cost model against the clock per subdomain, and one
// solve with each operator.
//                          break-even, and one solve with each operator
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/json.hpp"
#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "io/atomic_output.hpp"
#include "io/mesh_file.hpp"
#include "par/parallel.hpp"
#include "primal/one_body.hpp"
#include "study/bench_parts.hpp"

namespace dualcell::study::bench {

// Median seconds of `repeat` calls of f (after one untimed call).
template <class F>
double median_seconds(int repeat, F&& f) {
  f();
  std::vector<double> t(static_cast<std::size_t>(repeat));
  for (double& x : t) {
    const auto t0 = Clock::now();
    f();
    x = seconds_since(t0);
  }
  std::nth_element(t.begin(), t.begin() + repeat / 2, t.end());
  return t[static_cast<std::size_t>(repeat / 2)];
}

struct OperatorCell {
  std::string name;
  Scene scene;
  std::optional<mesh::Mesh> mesh = std::nullopt;  // none: the scene's mapped mesh
};

std::vector<OperatorCell> operator_cells(const BenchOptions& options) {
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
  if (!options.operators_scene.empty()) {
    const Scene scene = load_scene(options.operators_scene);
    io::MeshFile file = io::read_mesh(options.operators_mesh);
    if (const std::string problem = io::geometry_mismatch(file.mesh, scene); !problem.empty())
      throw InputError(options.operators_mesh.string() + ": not the mesh of " + options.operators_scene.string() +
                       ": " + problem);
    cells.push_back({options.operators_scene.stem().string(), scene, std::move(file.mesh)});
  }
  return cells;
}

// The cost model against the clock, per subdomain (docs/method.md §6a; feti/operator_cost.hpp),
// and one solve of each cell with each operator.
void dual_operators(const BenchOptions& options, std::ostringstream& md, JsonObject& json) {
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
  for (const OperatorCell& cell : operator_cells(options)) {
    const mesh::Mesh m = cell.mesh ? *cell.mesh : mesh::build_mesh(cell.scene.geometry);
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
      const double t_setup = seconds_since(t0);
      const double break_even = model.implicit_apply > model.explicit_apply
                                    ? model.explicit_setup / (model.implicit_apply - model.explicit_apply)
                                    : std::numeric_limits<double>::infinity();
      // Where the explicit product is no cheaper than the sweeps it never pays.
      const std::string break_even_text = std::isfinite(break_even) ? format("%.0f", break_even) : std::string("never");
      md << format("| %s | %s %d | %d | %d | %ld | %ld | %.1f / %.1f | %.2f / %.2f | %.1f / %.1f | %s |\n",
                   cell.name.c_str(), sub.is_fibre ? "fibre" : "matrix", sub.index, sub.n_dofs, e.n_rows,
                   static_cast<long>(nb), static_cast<long>(sub.K_plus->factor_nonzeros()), 1e6 * model.implicit_apply,
                   1e6 * t_implicit, 1e6 * model.explicit_apply, 1e6 * t_explicit, 1e3 * model.explicit_setup,
                   1e3 * t_setup, break_even_text.c_str());
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
      const double setup = seconds_since(t0);
      const feti::Solution r = solver.solve(sigma, solver.intact());
      if (!r.converged()) throw std::runtime_error(std::string("dual operators bench: ") + r.qp.message);
      solves << format("| %s | %s | %d of %d | %.4f | %.4f | %.4f | %ld |\n", cell.name.c_str(), to_string(op),
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

}  // namespace dualcell::study::bench

namespace dualcell::study {

std::string run_operators_only(const BenchOptions& options) {
  return bench::run_section_only(
      options, "operators", "# dualcell benchmark: dual operators\n",
      [&](std::ostringstream& md, JsonObject& json) { bench::dual_operators(options, md, json); });
}

}  // namespace dualcell::study
