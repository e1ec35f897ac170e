// dualcell-bench: the performance tables (issue: numerical scalability, the linear-solve floor,
// sweep steps, memory). Ratios are measured within one run, so a busy machine shifts them less
// than absolute times.
//
//   numerical scalability  blocks 1×1 … 32×32 at degree 2, and degrees 1 … 8 on a 4×4 block:
//                          outer and inner iterations and applications of F, compression along
//                          x, no adhesion, symmetry boundary, E_f/E_m = 100
//   floor                  one contact solve (setup + solve) against one CHOLMOD factorise and
//                          solve of the bonded problem as one body, same mesh, ~1e5 and ~1e6 DOF
//   sweep step             a further (warm-started, proportional) step against the first one
//   memory                 peak resident set per DOF of the contact solve at ~1e6 DOF
//
//   dualcell-bench --out-dir pipelines/out/bench [--quick]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <sys/resource.h>

#include "core/stage.hpp"
#include "feti/solver.hpp"
#include "io/atomic_output.hpp"
#include "study/monolithic.hpp"

namespace {

using namespace dualcell;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

Scene block(int cells, int degree, double strength = 0) {
  Scene s;
  s.geometry.cells = {cells, cells};
  s.geometry.cell_size = 1;
  s.geometry.fibre_radius = 0.3;
  s.geometry.degree = degree;
  s.fibre = {1e5, 0.2};
  s.matrix = {1e3, 0.4};
  s.interface = {strength, strength};
  s.load.boundary = Boundary::symmetry;
  s.solver.tolerance = 1e-8;
  return s;
}

long peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss * 1024L;
}

struct Run {
  int cells, degree, dofs, rows;
  long outer, steps, applications;
  double setup_seconds, solve_seconds;
  bool converged;
};

Run contact(int cells, int degree) {
  const Scene s = block(cells, degree);
  const auto t0 = Clock::now();
  const mesh::Mesh m = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(m, s);
  const double setup = since(t0);
  const auto t1 = Clock::now();
  const feti::Solution r = solver.solve({-10, 0, 0}, solver.intact());
  return {cells, degree, m.dim_u(), r.n_rows, r.outer_iterations, r.cg_steps + r.expansion_steps + r.proportioning_steps,
          r.operator_applications, setup, since(t1), r.converged()};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dualcell-bench: performance tables (scalability, floor, sweep step, memory) and summary.json"};
  std::string out_dir;
  bool quick = false;
  app.add_option("--out-dir", out_dir, "folder for scalability.md, floor.md and summary.json")->required();
  app.add_flag("--quick", quick, "small sizes only (a smoke test, not a measurement)");
  CLI11_PARSE(app, argc, argv);

  return run_stage("dualcell-bench", [&] {
    std::filesystem::create_directories(out_dir);
    io::AtomicOutputs outputs;
    const auto md_tmp = outputs.add(std::filesystem::path(out_dir) / "bench.md");
    const auto json_tmp = outputs.add(std::filesystem::path(out_dir) / "summary.json");
    std::ostringstream md, json;
    md << "# dualcell benchmark\n\nCompression along x, no adhesion, symmetry boundary, E_f/E_m = 100, r = 0.3, "
          "tolerance 1e-8. Seconds are wall time on this machine in this run.\n\n";

    // Numerical scalability in the block size.
    md << "## Numerical scalability: block size (degree 2)\n\n| cells | DOF | dim λ | outer | MPRGP steps | F applications "
          "| setup s | solve s |\n|---|---|---|---|---|---|---|---|\n";
    json << "{\n  \"scalability\": [";
    const std::vector<int> blocks = quick ? std::vector<int>{1, 2, 4} : std::vector<int>{1, 2, 4, 8, 16, 32};
    long ops_2x2 = 0, ops_largest = 0;
    bool first = true;
    auto row = [&](const Run& r) {
      char line[256];
      std::snprintf(line, sizeof line, "| %d×%d, k=%d | %d | %d | %ld | %ld | %ld | %.3f | %.3f |\n", r.cells, r.cells, r.degree,
                    r.dofs, r.rows, r.outer, r.steps, r.applications, r.setup_seconds, r.solve_seconds);
      md << line;
      std::snprintf(line, sizeof line,
                    "%s\n    {\"cells\": %d, \"degree\": %d, \"dofs\": %d, \"operator_applications\": %ld, "
                    "\"outer_iterations\": %ld, \"seconds\": %.6f, \"converged\": %s}",
                    first ? "" : ",", r.cells * r.cells, r.degree, r.dofs, r.applications, r.outer,
                    r.setup_seconds + r.solve_seconds, r.converged ? "true" : "false");
      json << line;
      first = false;
    };
    for (int n : blocks) {
      const Run r = contact(n, 2);
      if (n == 2) ops_2x2 = r.applications;
      ops_largest = r.applications;
      row(r);
    }
    md << "\nF applications, largest block against 2×2: " << static_cast<double>(ops_largest) / ops_2x2 << "\n\n";

    // Numerical scalability in the degree: fit applications ∝ (H/h)^q, H/h = 4k intervals per cell edge.
    md << "## Numerical scalability: degree (4×4 cells)\n\n| cells | DOF | dim λ | outer | MPRGP steps | F applications "
          "| setup s | solve s |\n|---|---|---|---|---|---|---|---|\n";
    const int max_degree = quick ? 3 : 8;
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n_fit = 0;
    for (int k = 1; k <= max_degree; ++k) {
      const Run r = contact(4, k);
      row(r);
      const double x = std::log(4.0 * k), y = std::log(static_cast<double>(r.applications));
      sx += x, sy += y, sxx += x * x, sxy += x * y, ++n_fit;
    }
    const double exponent = (n_fit * sxy - sx * sy) / (n_fit * sxx - sx * sx);
    md << "\nFitted growth of F applications with H/h: exponent " << exponent << " (target ≤ 0.5)\n\n";
    json << "\n  ],\n  \"degree_exponent\": " << exponent << ",\n  \"blocks_ratio_largest_to_2x2\": "
         << static_cast<double>(ops_largest) / ops_2x2 << ",\n";

    // Floor and memory.
    md << "## The floor: contact solve against one monolithic CHOLMOD solve\n\n| case | DOF | contact setup s | contact "
          "solve s | contact total s | CHOLMOD factorise+solve s | ratio | peak RSS bytes/DOF |\n|---|---|---|---|---|---|---|---|\n";
    json << "  \"floor\": [";
    const std::vector<std::pair<int, int>> floors = quick ? std::vector<std::pair<int, int>>{{4, 2}}
                                                          : std::vector<std::pair<int, int>>{{16, 3}, {32, 5}};
    double bytes_per_dof = 0;
    first = true;
    for (const auto& [n, k] : floors) {
      const Run r = contact(n, k);
      const long rss = peak_rss_bytes();
      const Scene bonded = block(n, k, 1e12);
      const mesh::Mesh m = mesh::build_mesh(bonded.geometry);
      feti::FetiSetup setup(m, bonded);
      const Eigen::VectorXd f = setup.load({-10, 0, 0});
      const auto t0 = Clock::now();
      const Eigen::VectorXd u = study::monolithic_solve(m, bonded, f, false, false);
      const double cholesky = since(t0);
      bytes_per_dof = static_cast<double>(rss) / r.dofs;
      const double total = r.setup_seconds + r.solve_seconds;
      char line[256];
      std::snprintf(line, sizeof line, "| %d×%d, k=%d | %d | %.2f | %.2f | %.2f | %.2f | %.1f | %.0f |\n", n, n, k, r.dofs,
                    r.setup_seconds, r.solve_seconds, total, cholesky, total / cholesky, bytes_per_dof);
      md << line;
      std::snprintf(line, sizeof line, "%s\n    {\"dofs\": %d, \"contact_seconds\": %.6f, \"cholesky_seconds\": %.6f}",
                    first ? "" : ",", r.dofs, total, cholesky);
      json << line;
      first = false;
    }
    md << "\nPeak RSS is the whole process's (it includes earlier rows); bytes/DOF at the largest case: "
       << bytes_per_dof << "\n\n";

    // Sweep step: a further proportional step against the first one (setup included).
    const auto [sn, sk] = quick ? std::pair<int, int>{4, 2} : std::pair<int, int>{16, 3};
    const Scene s = block(sn, sk);
    const auto t0 = Clock::now();
    const mesh::Mesh m = mesh::build_mesh(s.geometry);
    feti::ContactSolver solver(m, s);
    const feti::Solution first_step = solver.solve({-10, 0, 0}, solver.intact());
    const double first_seconds = since(t0);
    const Eigen::VectorXd lambda = 2 * first_step.lambda, multiplier = 2 * first_step.multiplier;
    const auto t1 = Clock::now();
    const feti::Solution second = solver.solve({-20, 0, 0}, solver.intact(), &lambda, &multiplier);
    const double second_seconds = since(t1);
    const double ratio = second_seconds / first_seconds;
    md << "## Sweep step\n\n" << sn << "×" << sn << " cells, degree " << sk << ": first step (setup + solve) "
       << first_seconds << " s, " << first_step.operator_applications << " F applications; a further step "
       << second_seconds << " s, " << second.operator_applications << " F applications: ratio " << ratio
       << " (target ≤ 0.1).\n\n## Threads\n\nSubdomain work runs on one thread in this version.\n";
    json << "\n  ],\n  \"sweep_step_ratio\": " << ratio << ",\n  \"bytes_per_dof\": " << bytes_per_dof
         << ",\n  \"threads\": 1\n}\n";
    std::ofstream(md_tmp) << md.str();
    std::ofstream(json_tmp) << json.str();
    outputs.commit();
    std::fputs(md.str().c_str(), stdout);
  });
}
