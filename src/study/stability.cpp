#include "study/stability.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "feti/solver.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::study {

std::vector<StabilityCase> stability_cases(bool fast) {
  struct Geometry {
    double radius, offset;
  };
  const std::vector<std::pair<Boundary, std::vector<double>>> boundaries = {
      {Boundary::symmetry, {0, 90}}, {Boundary::traction, {0, 30, 45, 90}}, {Boundary::periodic, {0, 30, 45, 90}}};
  const std::vector<double> ratios = fast ? std::vector<double>{1e-3, 1e6} : std::vector<double>{1e-3, 1, 1e3, 1e6};
  const std::vector<double> nus = fast ? std::vector<double>{0, 0.499} : std::vector<double>{0, 0.3, 0.45, 0.499};
  // Off-centre: ligament 0.03 between the fibre and the cell edge.
  const std::vector<Geometry> geometries =
      fast ? std::vector<Geometry>{{0.05, 0}, {0.3, 0.17}} : std::vector<Geometry>{{0.05, 0}, {0.3, 0}, {0.45, 0}, {0.3, 0.17}};
  const std::vector<std::string> adhesions = {"none", "tiny", "huge"};
  std::vector<StabilityCase> cases;
  for (const auto& [boundary, directions] : boundaries) {
    const std::vector<double> dirs = fast ? std::vector<double>{directions.back() == 90 && directions.size() > 2 ? 45.0 : 0.0}
                                          : directions;
    for (double direction : dirs) {
      // Materials × geometry × adhesion at unit load, tension and compression.
      for (double ratio : ratios)
        for (double nu : nus)
          for (const auto& g : geometries)
            for (const auto& adhesion : adhesions)
              for (double load : {1.0, -1.0}) {
                if (fast && adhesion == "huge") continue;
                cases.push_back({boundary, direction, ratio, nu, g.radius, g.offset, adhesion, load, 2});
              }
      // Load magnitudes over 18 orders on the base case.
      for (double load : {1e-12, -1e-12, 1e-3, -1e-3, 1e6, -1e6})
        for (const auto& adhesion : adhesions) cases.push_back({boundary, direction, 1e3, 0.3, 0.3, 0, adhesion, load, 2});
    }
  }
  return cases;
}

StabilityRow run_stability_case(const StabilityCase& c, double tolerance) {
  StabilityRow row;
  row.c = c;
  const auto t0 = std::chrono::steady_clock::now();
  Scene scene;
  scene.geometry.cells = {1, 1};
  scene.geometry.cell_size = 1;
  scene.geometry.fibre_radius = c.radius;
  scene.geometry.fibre_offset = {c.offset, 0};
  scene.geometry.degree = c.degree;
  scene.fibre = {c.stiffness_ratio, 0.2};
  scene.matrix = {1.0, c.nu_matrix};
  const double strength = c.adhesion == "tiny" ? 1e-6 : c.adhesion == "huge" ? 1e6 : 0.0;
  scene.interface = {strength, strength};
  scene.load.boundary = c.boundary;
  scene.solver.tolerance = tolerance;
  const double t = c.direction_deg * std::numbers::pi / 180;
  const Eigen::Vector3d N(std::cos(t) * std::cos(t), std::sin(t) * std::sin(t),
                          c.boundary == Boundary::symmetry ? 0.0 : std::cos(t) * std::sin(t));
  try {
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    feti::ContactSolver solver(m, scene);
    const feti::Solution s = solver.solve(c.load * N, solver.intact());
    row.status = qp::to_string(s.qp.status);
    row.primal_ok = s.primal_ok;
    row.message = s.qp_converged() ? s.primal_message : s.qp.message;
    row.finite = s.u.allFinite() && s.lambda.allFinite() && s.strain.allFinite();
    row.outer_iterations = s.outer_iterations;
    row.operator_applications = s.operator_applications;
    row.relative_projected_gradient = s.kkt.relative_projected_gradient;
    row.relative_equality_residual = s.kkt.relative_equality_residual;
    row.relative_equilibrium = s.kkt.relative_equilibrium;
    const double u_scale = s.u.lpNorm<Eigen::Infinity>();
    row.penetration = u_scale > 0 ? s.kkt.max_penetration / u_scale : 0;
    row.glue_jump = u_scale > 0 ? s.kkt.max_glue_jump / u_scale : 0;
    for (auto b : s.bonds) row.broken += scene.interface.has_adhesion() && !b;
    const double e_nn = N(0) * s.strain(0) + N(1) * s.strain(1) + 2 * N(2) * s.strain(2);
    row.modulus = c.load / e_nn;
    // Converged means checked and finite; otherwise a diagnostic must say why.
    row.ok = s.converged() ? row.finite : !row.message.empty();
  } catch (const std::exception& e) {
    row.status = "exception";
    row.message = e.what();
    row.ok = false;
  }
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return row;
}

}  // namespace dualcell::study
