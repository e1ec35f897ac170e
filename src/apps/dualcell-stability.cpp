// dualcell-stability: the stability matrix on stiff and extreme cases (src/study/stability.hpp).
// Writes a CSV with one row per case and a Markdown summary; exits 1 when a case failed (a
// silent NaN/Inf, or a stop without a diagnostic).
//
//   dualcell-stability --out stability.csv [--summary stability.md] [--fast]
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include "core/error.hpp"
#include "core/stage.hpp"
#include "io/atomic_output.hpp"
#include "study/stability.hpp"

int main(int argc, char** argv) {
  CLI::App app{"dualcell-stability: run the solver over stiffness contrasts, Poisson ratios, fibre sizes and\n"
               "positions, adhesion, load magnitudes, directions and boundary conditions; write a table."};
  std::string out, summary;
  bool fast = false;
  double tolerance = 1e-8;
  app.add_option("--out", out, "CSV, one row per case")->required();
  app.add_option("--summary", summary, "Markdown summary (per boundary and factor)");
  app.add_flag("--fast", fast, "the subset the test suite runs");
  app.add_option("--tolerance", tolerance, "solver tolerance")->check(CLI::Range(1e-14, 1e-2));
  CLI11_PARSE(app, argc, argv);

  int failures = 0;
  const int status = dualcell::run_stage("dualcell-stability", [&] {
    using namespace dualcell;
    const auto cases = study::stability_cases(fast);
    io::AtomicOutputs outputs;
    const auto csv_tmp = outputs.add(out);
    const auto md_tmp = summary.empty() ? std::filesystem::path() : outputs.add(summary);
    std::ofstream csv(csv_tmp);
    csv << "boundary,direction_deg,stiffness_ratio,nu_matrix,radius,offset,adhesion,load,status,primal_ok,finite,ok,"
           "outer_iterations,operator_applications,relative_projected_gradient,relative_equality_residual,"
           "relative_equilibrium,penetration_rel,glue_jump_rel,broken,modulus,seconds,message\n";
    struct Tally {
      int n = 0, converged = 0, failed = 0;
      long max_ops = 0;
      double max_gradient = 0, max_penetration = 0;
    };
    std::map<std::string, Tally> by_factor;
    const bool show = ::isatty(2);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const auto row = study::run_stability_case(cases[i], tolerance);
      const auto& c = row.c;
      std::string message = row.message;
      for (char& ch : message)
        if (ch == ',' || ch == '\n') ch = ';';
      csv << to_string(c.boundary) << ',' << c.direction_deg << ',' << c.stiffness_ratio << ',' << c.nu_matrix << ','
          << c.radius << ',' << c.offset << ',' << c.adhesion << ',' << c.load << ',' << row.status << ','
          << row.primal_ok << ',' << row.finite << ',' << row.ok << ',' << row.outer_iterations << ','
          << row.operator_applications << ',' << row.relative_projected_gradient << ','
          << row.relative_equality_residual << ',' << row.relative_equilibrium << ',' << row.penetration << ','
          << row.glue_jump << ',' << row.broken << ',' << row.modulus << ',' << row.seconds << ',' << message << '\n';
      failures += !row.ok;
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
      if (show) std::fprintf(stderr, "\rdualcell-stability: case %zu of %zu, %d failed   ", i + 1, cases.size(), failures);
    }
    if (show) std::fprintf(stderr, "\n");
    csv.close();
    if (!md_tmp.empty()) {
      std::ofstream md(md_tmp);
      md << "# Stability matrix (" << cases.size() << " cases, tolerance " << tolerance << ")\n\n"
         << "A case passes when it converges with its primal check passed and every result finite, or stops with a "
            "diagnostic. Per factor value:\n\n"
         << "| factor | cases | converged | failed | max F applications | max rel. projected gradient | max penetration / ‖u‖ |\n"
         << "|---|---|---|---|---|---|---|\n";
      for (const auto& [name, t] : by_factor)
        md << "| " << name << " | " << t.n << " | " << t.converged << " | " << t.failed << " | " << t.max_ops << " | "
           << t.max_gradient << " | " << t.max_penetration << " |\n";
    }
    outputs.commit();
    std::printf("dualcell-stability: %zu cases, %d failed -> %s\n", cases.size(), failures, out.c_str());
  });
  return status != 0 ? status : (failures > 0 ? 1 : 0);
}
