#include "study/stability.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <sstream>

#include "core/directions.hpp"
#include "core/error.hpp"
#include "core/progress.hpp"
#include "feti/solver.hpp"
#include "io/atomic_output.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::study {

std::vector<StabilityCase> stability_cases(bool fast) {
  struct Geometry {
    double radius, offset;
  };
  const std::vector<std::pair<Boundary, std::vector<double>>> boundaries = {
      {Boundary::symmetry, {0, 90}}, {Boundary::traction, {0, 30, 45, 90}}, {Boundary::periodic, {0, 30, 45, 90}}};
  const std::vector<double> ratios =
      fast ? std::vector<double>{1e-3, 1e6} : std::vector<double>{1e-6, 1e-3, 1, 1e3, 1e6};
  const std::vector<double> nus = fast ? std::vector<double>{0, 0.499} : std::vector<double>{0, 0.3, 0.45, 0.499};
  // Off-centre: ligament 0.03 between the fibre and the cell edge.
  const std::vector<Geometry> geometries = fast ? std::vector<Geometry>{{0.05, 0}, {0.3, 0.17}}
                                                : std::vector<Geometry>{{0.05, 0}, {0.3, 0}, {0.45, 0}, {0.3, 0.17}};
  const std::vector<std::string> adhesions = {"none", "tiny", "huge"};
  std::vector<StabilityCase> cases;
  for (Element element : {Element::p1, Element::p2})
    for (const auto& [boundary, directions] : boundaries) {
      const std::vector<double> dirs =
          fast ? std::vector<double>{directions.back() == 90 && directions.size() > 2 ? 45.0 : 0.0} : directions;
      for (double direction : dirs) {
        // Materials × geometry × adhesion at unit load, tension and compression.
        for (double ratio : ratios)
          for (double nu : nus)
            for (const auto& g : geometries)
              for (const auto& adhesion : adhesions)
                for (double load : {1.0, -1.0}) {
                  if (fast && adhesion == "huge") continue;
                  cases.push_back({boundary, direction, ratio, nu, g.radius, g.offset, adhesion, load, 2, element});
                }
        // Load magnitudes over 18 orders on the base case.
        for (double load : {1e-12, -1e-12, 1e-3, -1e-3, 1e6, -1e6})
          for (const auto& adhesion : adhesions)
            cases.push_back({boundary, direction, 1e3, 0.3, 0.3, 0, adhesion, load, 2, element});
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
  scene.geometry.element = c.element;
  scene.fibre = {c.stiffness_ratio, 0.2};
  scene.matrix = {1.0, c.nu_matrix};
  const double strength = c.adhesion == "tiny" ? 1e-6 : c.adhesion == "huge" ? 1e6 : 0.0;
  scene.interface = {strength, strength};
  scene.load.boundary = c.boundary;
  scene.solver.tolerance = tolerance;
  validate(scene);
  Eigen::Vector3d N = uniaxial_stress(c.direction_deg * std::numbers::pi / 180);
  if (c.boundary == Boundary::symmetry) N(2) = 0;
  try {
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    feti::ContactSolver solver(m, scene);
    const feti::Solution s = solver.solve(c.load * N, solver.intact());
    row.status = qp::to_string(s.qp.status);
    row.primal_ok = s.primal_ok;
    row.message = s.qp_converged() ? s.primal_message : s.qp.message;
    row.finite = s.u.allFinite() && s.lambda.allFinite() && s.strain.allFinite();
    row.outer_iterations = s.counters.outer_iterations;
    row.operator_applications = s.counters.operator_applications;
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
  row.seconds = seconds_since(t0);
  return row;
}

StabilityReport run_stability(const StabilityOptions& options) {
  StabilityReport report;
  const auto cases = stability_cases(options.fast);
  io::AtomicOutputs outputs;
  outputs.add(options.csv);
  if (!options.summary.empty()) outputs.add(options.summary);
  std::ostringstream csv;
  csv << "element,boundary,direction_deg,stiffness_ratio,nu_matrix,radius,offset,adhesion,load,status,primal_ok,finite,"
         "ok,"
         "outer_iterations,operator_applications,relative_projected_gradient,relative_equality_residual,"
         "relative_equilibrium,penetration_rel,glue_jump_rel,broken,modulus,seconds,message\n";
  struct Tally {
    int n = 0, converged = 0, failed = 0;
    long max_ops = 0;
    double max_gradient = 0, max_penetration = 0;
  };
  std::map<std::string, Tally> by_factor;
  const bool show = options.progress;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto row = run_stability_case(cases[i], options.tolerance);
    const auto& c = row.c;
    std::string message = row.message;
    for (char& ch : message)
      if (ch == ',' || ch == '\n') ch = ';';
    csv << to_string(c.element) << ',' << to_string(c.boundary) << ',' << c.direction_deg << ',' << c.stiffness_ratio
        << ',' << c.nu_matrix << ',' << c.radius << ',' << c.offset << ',' << c.adhesion << ',' << c.load << ','
        << row.status << ',' << row.primal_ok << ',' << row.finite << ',' << row.ok << ',' << row.outer_iterations
        << ',' << row.operator_applications << ',' << row.relative_projected_gradient << ','
        << row.relative_equality_residual << ',' << row.relative_equilibrium << ',' << row.penetration << ','
        << row.glue_jump << ',' << row.broken << ',' << row.modulus << ',' << row.seconds << ',' << message << '\n';
    report.failed += !row.ok;
    report.stopped += row.ok && !(row.status == "converged" && row.primal_ok);
    auto tally = [&](const std::string& key) {
      Tally& t = by_factor[key];
      ++t.n;
      t.converged += row.status == "converged" && row.primal_ok;
      t.failed += !row.ok;
      t.max_ops = std::max(t.max_ops, row.operator_applications);
      if (std::isfinite(row.relative_projected_gradient))
        t.max_gradient = std::max(t.max_gradient, row.relative_projected_gradient);
      if (std::isfinite(row.penetration)) t.max_penetration = std::max(t.max_penetration, row.penetration);
    };
    char key[96];
    tally(std::string("element ") + to_string(c.element));
    tally(std::string("boundary ") + to_string(c.boundary));
    std::snprintf(key, sizeof key, "E_f/E_m %g", c.stiffness_ratio);
    tally(key);
    std::snprintf(key, sizeof key, "nu_m %g", c.nu_matrix);
    tally(key);
    std::snprintf(key, sizeof key, "r %g offset %g", c.radius, c.offset);
    tally(key);
    tally("adhesion " + c.adhesion);
    std::snprintf(key, sizeof key, "|load| %g", std::abs(c.load));
    tally(key);
    if (show)
      std::fprintf(stderr, "\rdualcell-stability: case %zu of %zu, %d failed   ", i + 1, cases.size(), report.failed);
  }
  if (show) std::fprintf(stderr, "\n");
  outputs.write(options.csv, csv.str());
  if (!options.summary.empty()) {
    std::ostringstream md;
    md << "# Stability matrix (" << cases.size() << " cases, tolerance " << options.tolerance << ")\n\n"
       << "A case passes when it converges with its primal check passed and every result finite, or stops with a "
          "diagnostic. Per factor value:\n\n"
       << "| factor | cases | converged | failed | max F applications | max rel. projected gradient | max penetration "
          "/ ‖u‖ |\n"
       << "|---|---|---|---|---|---|---|\n";
    for (const auto& [name, t] : by_factor)
      md << "| " << name << " | " << t.n << " | " << t.converged << " | " << t.failed << " | " << t.max_ops << " | "
         << t.max_gradient << " | " << t.max_penetration << " |\n";
    outputs.write(options.summary, md.str());
  }
  outputs.commit();
  report.cases = static_cast<int>(cases.size());
  return report;
}

}  // namespace dualcell::study
