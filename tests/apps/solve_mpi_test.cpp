// dualcell-solve under mpiexec (1, 2, 3 ranks, oversubscribed on this 2-core machine): the
// subdomains are shared out over the ranks, λ is replicated, and rank 0 writes solution.h5.
// Any number of ranks gives the serial solution to 1e-12 with the same iteration counts, the
// contract of docs/method.md §16 (by construction the bits are the serial ones: a row of B
// couples at most two subdomains, so the ranks' row sums added in rank order are the serial
// sums; the tolerance leaves room for a B that couples more); a fixed number of ranks repeats
// itself bit for bit; a rank's memory holds only its share of the subdomain data, so a problem
// too large for one process under a memory limit solves on two; bad input stops every rank
// with one message. Skipped in a build without MPI or without mpiexec.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/exit_codes.hpp"
#include "io/hdf5.hpp"
#include "par/parallel.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

using io::any_extent;
using testing::bin;
using testing::mpiexec;
using testing::run_command;

// The solver's counters, which must not depend on the number of ranks.
const char* const counters[] = {"operator_applications", "outer_iterations",    "cg_steps",
                                "expansion_steps",       "proportioning_steps", "preconditioner_applications",
                                "debond_rounds",         "newly_broken",        "tightenings"};

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

class SolveMpi : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!par::built_with_mpi()) GTEST_SKIP() << "built without MPI";
    if (run_command("command -v mpiexec").exit_code != 0) GTEST_SKIP() << "no mpiexec";
  }
  // Writes the scene, meshes it and solves it serially (no launcher) into serial.h5.
  void prepare(const std::string& scene_text, const std::string& stress) {
    scene_ = dir_.write("s.toml", scene_text);
    mesh_ = dir_ / "mesh.h5";
    const auto m =
        run_command(bin("dualcell-mesh") + " --quiet --config " + scene_.string() + " --out " + mesh_.string());
    ASSERT_EQ(m.exit_code, 0) << m.output;
    stress_ = stress.empty() ? "" : " --stress " + stress;
    const auto serial = run_command(solve_command("") + (dir_ / "serial.h5").string());
    ASSERT_EQ(serial.exit_code, 0) << serial.output;
  }
  std::string solve_command(const std::string& launcher) const {
    return launcher + bin("dualcell-solve") + " --quiet --threads 1 --config " + scene_.string() + " --mesh " +
           mesh_.string() + stress_ + " --out ";
  }
  // `file` against serial.h5: the fields to 1e-12 of their largest entry, bonds and counters
  // exactly; "" when they agree.
  std::string compare_with_serial(const std::string& file, const std::vector<std::string>& fields) const {
    const io::File a = io::File::open_read(dir_ / "serial.h5"), b = io::File::open_read(dir_ / file);
    std::ostringstream out;
    for (const std::string& name : fields) {
      const io::Shape shape = a.shape(name);
      const auto x = a.read_doubles(name, shape), y = b.read_doubles(name, shape);
      double worst = 0;
      for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(x[i] - y[i]));
      if (worst > 1e-12 * max_abs(x)) out << name << ": differs by " << worst << " of " << max_abs(x) << "\n";
    }
    if (a.read_ints("/interface/bonded", {any_extent}) != b.read_ints("/interface/bonded", {any_extent}))
      out << "/interface/bonded differs\n";
    for (const char* c : counters)
      if (a.read_int_attribute_value("/solver", c) != b.read_int_attribute_value("/solver", c))
        out << c << ": " << b.read_int_attribute_value("/solver", c) << ", serial "
            << a.read_int_attribute_value("/solver", c) << "\n";
    return out.str();
  }
  testing::ScratchDir dir_;
  std::filesystem::path scene_, mesh_;
  std::string stress_;
};

// A periodic 3×2 block with adhesion whose bonds break under the load (debonding rounds, the
// macro subdomain on the last rank) and the Dirichlet preconditioner (K_ii⁻¹ on the owners).
const std::string debonding_block =
    testing::scene_text(3, 2, 2, 0.3,
                        "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n"
                        "[load]\nboundary = \"periodic\"\n[solver]\npreconditioner = \"dirichlet\"\n");
const std::string debonding_stress = "0.3,0.1,0.05";

TEST_F(SolveMpi, AnyNumberOfRanksGivesTheSerialSolutionWithTheSameIterations) {
  prepare(debonding_block, debonding_stress);
  const io::File serial = io::File::open_read(dir_ / "serial.h5");
  ASSERT_GT(serial.read_int_attribute_value("/solver", "newly_broken"), 0) << "the load must break bonds";
  const auto serial_bytes = serial.read_ints("/ranks/subdomain_bytes", {1});
  const auto serial_dofs = serial.read_ints("/ranks/dofs", {1});
  for (int ranks : {1, 2, 3}) {
    const std::string out = std::to_string(ranks) + "-ranks.h5";
    const auto r = run_command(solve_command(mpiexec(ranks)) + (dir_ / out).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(compare_with_serial(out, {"/solution/u", "/interface/lambda", "/macro/strain"}), "") << ranks;
    // The subdomains are shared out, not copied: the ranks' data adds up to the serial data,
    // and each rank's DOFs exceed an even share by less than one subdomain (runs balanced by
    // DOFs, each subdomain to the rank of its middle DOF; a subdomain is less than a cell, 1/6).
    const io::File f = io::File::open_read(dir_ / out);
    const auto bytes = f.read_ints("/ranks/subdomain_bytes", {static_cast<hsize_t>(ranks)});
    const auto dofs = f.read_ints("/ranks/dofs", {static_cast<hsize_t>(ranks)});
    EXPECT_EQ(std::accumulate(bytes.begin(), bytes.end(), std::int64_t{0}), serial_bytes[0]) << ranks;
    EXPECT_EQ(std::accumulate(dofs.begin(), dofs.end(), std::int64_t{0}), serial_dofs[0]) << ranks;
    const std::int64_t largest_subdomain = serial_dofs[0] / 6;
    for (auto d : dofs) EXPECT_LE(d, serial_dofs[0] / ranks + largest_subdomain) << ranks;
    const auto exchanges = f.read_ints("/ranks/exchanges", {static_cast<hsize_t>(ranks)});
    // One exchange per application of F or M⁻¹ on every rank (none alone).
    for (auto e : exchanges) EXPECT_EQ(e, exchanges[0]);
    if (ranks > 1) {
      EXPECT_GE(exchanges[0], serial.read_int_attribute_value("/solver", "operator_applications"));
    }
  }
}

// The explicit dual operator on every subdomain: each rank forms F_s of the subdomains it owns
// (their K⁺(b, b) never leaves it), and 2 ranks give the serial solution and counts.
TEST_F(SolveMpi, ExplicitOperatorsOnTwoRanksGiveTheSerialSolution) {
  std::string scene = debonding_block;
  scene.replace(scene.find("[solver]\n"), 9, "[solver]\ndual_operator = \"explicit\"\n");
  prepare(scene, debonding_stress);
  const io::File serial = io::File::open_read(dir_ / "serial.h5");
  ASSERT_EQ(serial.read_int_attribute_value("/solver", "explicit_subdomains"),
            serial.read_int_attribute_value("/solver", "subdomains"));
  const auto r = run_command(solve_command(mpiexec(2)) + (dir_ / "2-ranks.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(compare_with_serial("2-ranks.h5", {"/solution/u", "/interface/lambda", "/macro/strain"}), "");
  EXPECT_EQ(io::File::open_read(dir_ / "2-ranks.h5").read_int_attribute_value("/solver", "explicit_subdomains"),
            serial.read_int_attribute_value("/solver", "explicit_subdomains"));
}

// A resolved structure (boundary = "edges"): load steps with the bond history, on 2 ranks.
TEST_F(SolveMpi, AResolvedStructureOnTwoRanksGivesTheSerialSteps) {
  prepare(testing::scene_text(4, 1, 2, 0.3,
                              "[interface]\nnormal_strength = 0.02\ntangential_strength = 0.02\n[load]\nboundary = "
                              "\"edges\"\n[edges.left]\ntype = \"fixed\"\n[edges.right]\ntype = \"traction\"\n"
                              "traction = [0, -0.01]\n[steps]\nfactors = [0.5, 2.0, 0.5]\n[output]\nwatch = [2, 0]\n"),
          "");
  const auto r = run_command(solve_command(mpiexec(2)) + (dir_ / "2-ranks.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(compare_with_serial("2-ranks.h5", {"/solution/u", "/interface/lambda", "/steps/watch_displacement"}), "");
  const io::File a = io::File::open_read(dir_ / "serial.h5"), b = io::File::open_read(dir_ / "2-ranks.h5");
  EXPECT_EQ(a.read_ints("/steps/operator_applications", {3}), b.read_ints("/steps/operator_applications", {3}));
  EXPECT_EQ(a.read_ints("/steps/broken", {3}), b.read_ints("/steps/broken", {3}));
  EXPECT_GT(a.read_ints("/steps/broken", {3})[1], 0) << "the second step must break bonds";
  // The rank table counts the exchanges of every step, at least one per F application.
  const auto applications = b.read_ints("/steps/operator_applications", {3});
  for (auto e : b.read_ints("/ranks/exchanges", {2}))
    EXPECT_GE(e, std::accumulate(applications.begin(), applications.end(), std::int64_t{0}));
}

// Two runs on the same number of ranks write the same file, bit for bit but for the timings and
// the memory measured (h5diff's report lists nothing else).
TEST_F(SolveMpi, AFixedNumberOfRanksRepeatsItselfBitForBit) {
  prepare(debonding_block, debonding_stress);
  for (const char* out : {"a.h5", "b.h5"}) {
    const auto r = run_command(solve_command(mpiexec(3)) + (dir_ / out).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  EXPECT_EQ(testing::h5diff_except(dir_ / "a.h5", dir_ / "b.h5",
                                   {"<seconds_", "</ranks/seconds_", "</ranks/peak_rss_bytes>"}),
            "");
}

// The subdomain data of this block (2×2 cells at degree 16 with the Dirichlet preconditioner,
// 135 000 DOFs) is 218 MiB: measured, a process needs 260–300 MB of data segment (ulimit -d) to
// solve it alone, 180–200 MB per rank on 2 ranks (the rest is what every rank holds: the mesh,
// B and G, the dual vectors, the libraries' and OpenMPI's own). Under a limit of 240 MB one
// process stops with "out of memory" and two ranks solve it. The limit is on each process's
// private writable memory (RLIMIT_DATA), which AddressSanitizer's shadow memory would exceed;
// OPENBLAS_NUM_THREADS=1 because OpenBLAS's worker threads retry a failed buffer allocation for
// ever instead of failing.
TEST_F(SolveMpi, AProblemTooLargeForOneProcessUnderAMemoryLimitSolvesOnTwoRanks) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "a data-segment limit cannot hold AddressSanitizer's shadow memory";
#endif
  prepare(testing::scene_text(2, 2, 16, 0.3,
                              "[interface]\nnormal_strength = 1000.0\ntangential_strength = 1000.0\n[load]\nboundary = "
                              "\"symmetry\"\n[solver]\ntolerance = 1e-6\npreconditioner = \"dirichlet\"\n"),
          "0.01,0,0");
  const std::string limit = "ulimit -d 240000; OPENBLAS_NUM_THREADS=1 ";
  const auto alone = run_command("(" + limit + solve_command("") + (dir_ / "alone.h5").string() + ")");
  // Out of memory is an input too large for what this process may hold: exit 1, with the limit.
  EXPECT_EQ(alone.exit_code, exit_input_error) << alone.output;
  EXPECT_NE(alone.output.find("out of memory: the input needs more than is free of this process's limit of 0.25 GB"),
            std::string::npos)
      << alone.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "alone.h5"));
  const auto two = run_command("(" + limit + solve_command(mpiexec(2)) + (dir_ / "two.h5").string() + ")");
  ASSERT_EQ(two.exit_code, 0) << two.output;
  EXPECT_EQ(compare_with_serial("two.h5", {"/solution/u", "/interface/lambda"}), "");
}

// A position of a resolved structure's scene that is not a node of its mesh is an input error
// found while the inputs are read, before any rank starts work: one message, exit 1.
TEST_F(SolveMpi, APositionOffTheMeshStopsEveryRankWithOneMessage) {
  scene_ = dir_.write("s.toml", testing::scene_text(2, 1, 1, 0.3,
                                                    "[load]\nboundary = \"edges\"\n[edges.left]\ntype = \"fixed\"\n"
                                                    "[edges.right]\ntype = \"traction\"\ntraction = [0, -0.01]\n"
                                                    "[output]\nwatch = [1.5, 0.123]\n"));
  mesh_ = dir_ / "mesh.h5";
  ASSERT_EQ(
      run_command(bin("dualcell-mesh") + " --quiet --config " + scene_.string() + " --out " + mesh_.string()).exit_code,
      0);
  const auto r = run_command(solve_command(mpiexec(3)) + (dir_ / "x.h5").string());
  EXPECT_EQ(r.exit_code, exit_input_error) << r.output;
  EXPECT_EQ(testing::occurrences(r.output, "dualcell-solve: error:"), 1u) << r.output;
  EXPECT_NE(r.output.find("[output] watch at (1.5, 0.123): no node of the mesh there"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.h5"));
}

TEST_F(SolveMpi, BadInputStopsEveryRankWithOneMessage) {
  prepare(debonding_block, debonding_stress);
  const auto r =
      run_command(solve_command(mpiexec(3)) + (dir_ / "x.h5").string() + " --bonds " + (dir_ / "absent.h5").string());
  EXPECT_EQ(r.exit_code, exit_input_error) << r.output;
  EXPECT_EQ(testing::occurrences(r.output, "dualcell-solve: error:"), 1u) << r.output;
  EXPECT_NE(r.output.find("absent.h5"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.h5"));
}

}  // namespace
}  // namespace dualcell
