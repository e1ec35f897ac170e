// The benchmark's exact-law section: one cell's condensed law per evaluation against its full solve.
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
      solve_seconds = std::min(solve_seconds, seconds_since(t0));
    }
    const law::CondensedCell cell = feti::condense(solver.setup());
    law::CellEvaluator law(cell);
    // 400 stresses turning once about the sphere of (σxx, σyy, √2σxy), each of size 0.01, or half
    // the debond onset along it where that is smaller (bonded_load).
    std::vector<Eigen::Vector3d> path;
    for (int k = 0; k < 400; ++k) {
      const double t = 2 * std::numbers::pi * k / 400;
      const Eigen::Vector3d N(std::cos(t), std::sin(t) * std::cos(3 * t),
                              std::sin(t) * std::sin(3 * t) / std::sqrt(2.0));
      path.push_back(std::min(0.01, law.bonded_load(N)) * N);
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
      return 1e3 * seconds_since(t0) / static_cast<double>(path.size());
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

}  // namespace dualcell::study::bench

namespace dualcell::study {

std::string run_exact_law_only(const BenchOptions& options) {
  return bench::run_section_only(options, "exact_law", "", bench::exact_law);
}

}  // namespace dualcell::study
