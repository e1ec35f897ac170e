#pragma once
// The performance study behind `make -C pipelines bench` (what it measures: study/bench.cpp).
#include <filesystem>
#include <string>

namespace dualcell::study {

struct BenchOptions {
  std::filesystem::path out_dir;  // bench.md and summary.json go here (atomically)
  bool quick = false;             // small sizes only: a smoke test, not a measurement
  int threads = 0;                // for the multi-threaded rows; 0 = all OpenMP offers
  // The dual operators' section also measures the matrix subdomain of this cell (scene, mesh.h5),
  // e.g. a random RVE, whose F_s is far larger than the built-in cells' (empty: none).
  std::filesystem::path operators_scene, operators_mesh;
};

// Runs the study, writes bench.md and summary.json, and returns the Markdown report.
std::string run_bench(const BenchOptions& options);
// Only the floor (contact solve against one CHOLMOD solve, p1 and p2): floor.md and floor.json,
// naming the BLAS the process loaded, so that runs on different BLAS libraries can be compared.
std::string run_floor_only(const BenchOptions& options);
// Only the exact law (one cell's condensed law per evaluation against its full solve):
// exact_law.md and exact_law.json.
std::string run_exact_law_only(const BenchOptions& options);
// Only the dual operators (the cost model against the clock per subdomain, one solve with each
// operator): operators.md and operators.json.
std::string run_operators_only(const BenchOptions& options);
// Only the compact laws of one law.h5 against its exact law, error against the cost of an
// evaluation (docs/method.md §16c): small_cell.md and small_cell.json.
std::string run_small_cell_only(const BenchOptions& options, const std::filesystem::path& law_file);

}  // namespace dualcell::study
