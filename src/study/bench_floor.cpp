// The benchmark's floor: one contact solve against one CHOLMOD solve of the bonded problem as
// one body, same mesh, p1 and p2, ~1e5 and ~1e6 DOF, with the BLAS the process loaded.
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

// The BLAS this process runs on: the file behind libblas.so.3 (or an OpenBLAS library) among
// the loaded objects, as /proc/self/maps lists them.
std::string loaded_blas() {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    if (path.find("libblas") != std::string::npos || path.find("openblas") != std::string::npos) {
      std::error_code ec;
      const auto real = std::filesystem::canonical(path, ec);
      return ec ? path : real.string();
    }
  }
  return "none loaded";
}

// The floor: one contact solve (setup + solve, `threads` threads) against CHOLMOD's analyse,
// factorise and solve of the bonded problem as one body on the same mesh, for both element
// orders at ~1e5 and ~1e6 DOF.
Floor run_floor(int threads, bool quick) {
  Progress progress("dualcell-bench", true);
  struct Case {
    int cells, degree;
    Element element;
  };
  // p2 at degree k has the DOFs of p1 at 2k: 12×12 k=2 and 40×40 k=2 match the p1 rows' sizes.
  const std::vector<Case> cases =
      quick ? std::vector<Case>{{4, 2, Element::p1}, {4, 1, Element::p2}}
            : std::vector<Case>{{16, 3, Element::p1}, {12, 2, Element::p2}, {32, 5, Element::p1}, {40, 2, Element::p2}};
  const std::string blas = loaded_blas();
  Floor out;
  int largest_dofs = 0;
  std::ostringstream md;
  md << "## The floor: contact solve against one monolithic CHOLMOD solve\n\nThe contact solve (assembly, "
        "factorisations, dual setup, QP, recovery) on up to "
     << threads
     << " thread(s), no preconditioner; against CHOLMOD's analyse, factorise and solve of the assembled bonded "
        "problem as one body (supernodal, automatic ordering) on the BLAS this process loaded: "
     << blas
     << ". The mesh is timed in neither.\n\n| case | DOF | contact setup s | contact solve s | contact total s | "
        "CHOLMOD "
        "factorise+solve s | ratio | peak RSS bytes/DOF |\n|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto [n, k, element] = cases[i];
    Run r = contact(n, k, threads, Preconditioner::none, element, &progress);
    const long rss = par::peak_rss_bytes();
    const Scene bonded = block(n, k, Preconditioner::none, 1e12, element);
    const mesh::Mesh m = mesh::build_mesh(bonded.geometry);
    double cholesky = 0;  // same mesh and load (the load does not depend on the bonds)
    primal::solve_one_body(m, bonded, r.f, false, false, &cholesky);
    const double total = r.setup_seconds + r.solve_seconds;
    // The peak resident set is the process's: it says something about a row only when that row
    // is the largest problem so far.
    const bool largest = r.dofs >= largest_dofs;
    largest_dofs = std::max(largest_dofs, r.dofs);
    if (largest) out.bytes_per_dof = static_cast<double>(rss) / r.dofs;
    const std::string memory =
        largest ? format("%.0f", static_cast<double>(rss) / r.dofs) : std::string("(earlier rows)");
    md << format("| %d×%d, k=%d %s | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %s |\n", n, n, k, to_string(element),
                 r.dofs, r.setup_seconds, r.solve_seconds, total, cholesky, total / cholesky, memory.c_str());
    out.json.push_back(JsonObject()
                           .add_text("element", to_string(element))
                           .add("dofs", std::to_string(r.dofs))
                           .add("contact_seconds", json_number(total))
                           .add("cholesky_seconds", json_number(cholesky))
                           .add("contact_threads", std::to_string(r.threads))
                           .add_text("blas", blas)
                           .str(6));
    out.runs.push_back(std::move(r));
  }
  md << "\nTargets: ratio ≤ 3 at ~1e5 DOF and ≤ 2 at ~1e6 DOF. Peak RSS is the whole process's (it includes "
        "earlier rows); bytes/DOF at the largest case: "
     << out.bytes_per_dof << " (target ≤ 2048).\n";
  out.md = md.str();
  return out;
}

// Sweep step: a further proportional step against the first one (setup included).

}  // namespace dualcell::study::bench

namespace dualcell::study {

std::string run_floor_only(const BenchOptions& options) {
  const int all = options.threads > 0 ? options.threads : omp_get_max_threads();
  return bench::run_section_only(options, "floor", "", [&](std::ostringstream& md, JsonObject& json) {
    const bench::Floor floor = bench::run_floor(all, options.quick);
    md << floor.md;
    json.add_text("blas", bench::loaded_blas()).add("floor", json_list(floor.json));
  });
}

}  // namespace dualcell::study
