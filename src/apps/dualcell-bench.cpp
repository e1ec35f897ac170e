// dualcell-bench: the performance tables and summary.json (study/bench.hpp): numerical
// scalability, preconditioners, the linear-solve floor, threads, sweep steps, memory, the exact law.
//
//   dualcell-bench --out-dir pipelines/out/bench [--quick] [--floor-only] [--exact-law-only] [--operators-only]
//                  [--small-cell law.h5]
//   [--threads N]
#include <cstdio>

#include "apps/options.hpp"
#include "stage/stage.hpp"
#include "study/bench.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-bench: performance tables (scalability, preconditioners, floor, threads, sweep step, "
      "memory) and summary.json"};
  dualcell::study::BenchOptions options;
  app.add_option("--out-dir", options.out_dir, "folder for bench.md and summary.json")->required();
  app.add_flag("--quick", options.quick, "small sizes only (a smoke test, not a measurement)");
  bool floor_only = false;
  app.add_flag("--floor-only", floor_only,
               "only the floor (contact solve against one CHOLMOD solve, p1 and p2): floor.md, floor.json");
  bool exact_law_only = false;
  app.add_flag("--exact-law-only", exact_law_only,
               "only the exact law against the full solve of its cell: exact_law.md, exact_law.json");
  bool operators_only = false;
  app.add_flag("--operators-only", operators_only,
               "only the dual operators (cost model against the clock, one solve with each): operators.md, "
               "operators.json");
  std::vector<std::string> operators_cell;
  app.add_option("--operators-cell", operators_cell,
                 "SCENE.toml MESH.h5: the dual operators' section also measures this cell (e.g. a random RVE, "
                 "whose matrix subdomain has a large F_s)")
      ->expected(2);
  std::string small_cell_law;
  app.add_option("--small-cell", small_cell_law,
                 "only the compact laws of this law.h5 (with an exact law, no adhesion) against its exact law, error "
                 "against evaluation cost: small_cell.md, small_cell.json");
  app.add_option("--threads", options.threads, "threads for the multi-threaded rows; 0 = OMP_NUM_THREADS or all cores")
      ->check(dualcell::number_in(0, 4096));
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;
  if (operators_cell.size() == 2)
    options.operators_scene = operators_cell[0], options.operators_mesh = operators_cell[1];
  return dualcell::run_stage("dualcell-bench", [&] {
    using namespace dualcell::study;
    std::fputs((!small_cell_law.empty() ? run_small_cell_only(options, small_cell_law)
                : floor_only            ? run_floor_only(options)
                : exact_law_only        ? run_exact_law_only(options)
                : operators_only        ? run_operators_only(options)
                                        : run_bench(options))
                   .c_str(),
               stdout);
  });
}
