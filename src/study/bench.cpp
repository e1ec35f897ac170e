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
#include "study/bench_parts.hpp"

namespace dualcell::study {

using namespace bench;

namespace {

void sweep_step(bool quick, int all, std::ostringstream& md, JsonObject& json) {
  std::fprintf(stderr, "dualcell-bench: sweep step\n");
  const auto [sn, sk] = quick ? std::pair<int, int>{4, 2} : std::pair<int, int>{16, 3};
  const Scene s = block(sn, sk);
  const auto t0 = Clock::now();
  const mesh::Mesh m = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(m, s, all);
  const feti::Solution first_step = solver.solve({-10, 0, 0}, solver.intact());
  const double first_seconds = seconds_since(t0);
  const Eigen::VectorXd lambda = 2 * first_step.lambda, multiplier = 2 * first_step.multiplier;
  const auto t1 = Clock::now();
  const feti::Solution second = solver.solve({-20, 0, 0}, solver.intact(), &lambda, &multiplier);
  const double second_seconds = seconds_since(t1);
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
// alternated three times, the fastest of each compared (docs/guide/solve.md, "Progress").
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
  dual_operators(options, md, json);
  outputs.write(md_file, md.str());
  outputs.write(json_file, json.str() + "\n");
  outputs.commit();
  return md.str();
}

}  // namespace dualcell::study
