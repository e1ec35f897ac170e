#pragma once
// The benchmark's shared parts (study/bench.cpp and its sections in bench_floor.cpp,
// bench_exact_law.cpp, bench_operators.cpp): the block scenes it solves, one timed contact solve
// and its table rows, and the writing of one section alone.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "core/progress.hpp"
#include "core/scene.hpp"
#include "feti/solver.hpp"
#include "io/atomic_output.hpp"
#include "study/bench.hpp"

namespace dualcell::study::bench {

using Clock = std::chrono::steady_clock;  // timed with seconds_since (core/progress.hpp)

// The benchmark's block: cells × cells of fibres (E_f/E_m = 100, r = 0.3), symmetry boundary,
// tolerance 1e-8.
Scene block(int cells, int degree, Preconditioner preconditioner = Preconditioner::none, double strength = 0,
            Element element = Element::p1);

inline std::string format(const char* pattern, auto... values) {
  char line[512];
  std::snprintf(line, sizeof line, pattern, values...);
  return line;
}

struct Run {
  int cells, degree, dofs;
  Element element;
  long rows;
  int threads;
  Preconditioner preconditioner;
  long outer, cg, expansion, proportioning, applications, preconditioner_applications;
  double setup_seconds, solve_seconds;
  feti::Timings phases;
  bool converged;
  Eigen::VectorXd lambda, u, f;
};

// progress: the solve's phases and QP iterations on stderr while it works (the big cases run
// for minutes); it reads a clock per F application and prints only when a line is due.
Run contact(int cells, int degree, int threads, Preconditioner preconditioner = Preconditioner::none,
            Element element = Element::p1, Progress* progress = nullptr);
// Least-squares slope of log(applications) against log(H/h), H/h = 4k intervals per cell edge.
double degree_exponent(const std::vector<Run>& runs);
inline constexpr const char* run_header =
    "| cells | DOF | dim λ | outer | CG | expansion | proportioning | F applications | M⁻¹ applications | setup s | "
    "solve s |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
std::string run_row(const Run& r);
std::string run_json(const Run& r);
// Where the time of one solve goes, per phase (setup once per mesh and material; the rest per load).
std::string phase_row(const char* name, const Run& r);
inline constexpr const char* phase_header =
    "| case | threads | assembly | factorisation | dual setup (B, G, GGᵀ) | QP: F | QP: Q (coarse) | QP: M⁻¹ | QP: "
    "other (vectors, d, λ₀) | recovery |\n|---|---|---|---|---|---|---|---|---|---|\n";

// One line on stderr: which part of the benchmark runs.
void progress(const char* what);

// The floor (bench_floor.cpp): one contact solve against one CHOLMOD solve of the bonded problem.
struct Floor {
  std::string md;
  std::vector<std::string> json;
  std::vector<Run> runs;
  double bytes_per_dof = 0;
};
Floor run_floor(int threads, bool quick);
// The BLAS this process runs on.
std::string loaded_blas();
// The exact law against the full solve (bench_exact_law.cpp), and the dual operators' cost model
// against the clock (bench_operators.cpp): a section of bench.md and summary.json each.
void exact_law(std::ostringstream& md, JsonObject& json);
void dual_operators(const BenchOptions& options, std::ostringstream& md, JsonObject& json);

// One section of the benchmark alone: <name>.md and <name>.json in the output folder, written
// together or not at all.
template <class Section>
std::string run_section_only(const BenchOptions& options, const std::string& name, const std::string& title,
                             Section&& section) {
  std::filesystem::create_directories(options.out_dir);
  io::AtomicOutputs outputs;
  const auto md_file = options.out_dir / (name + ".md"), json_file = options.out_dir / (name + ".json");
  outputs.add(md_file);
  outputs.add(json_file);
  std::ostringstream md;
  JsonObject json;
  md << title;
  section(md, json);
  outputs.write(md_file, md.str());
  outputs.write(json_file, json.str() + "\n");
  outputs.commit();
  return md.str();
}

}  // namespace dualcell::study::bench
