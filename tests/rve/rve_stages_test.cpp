// An RVE through the stages that the square cells go through: with adhesion past the fuse (the
// sweep brackets the jump, the exact law replays every point of it, broken bonds included), and
// under mpiexec (paths over ranks, and one path's subdomains over a group of ranks), where
// sweep.h5 must be the serial one but for the seconds. Two fibres, one cut by the left and right
// sides, so that the periodic rows of a cut fibre, its joint modes and the matrix's METIS parts
// all take part.
#include <gtest/gtest.h>

#include <cmath>

#include "core/exit_codes.hpp"
#include "io/law_file.hpp"
#include "io/sweep_file.hpp"
#include "par/parallel.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;
using testing::run_command;

std::string q(const std::filesystem::path& p) { return testing::quoted(p); }

// subdomain_dofs 300: the matrix is split into several METIS parts (glue rows between them).
const std::string rve_text =
    "[geometry]\nsize = [1.0, 1.0]\nkind = \"list\"\ndegree = 2\n\n"
    "[[fibres]]\ncentre = [0.0, 0.5]\nradius = 0.2\n\n"
    "[[fibres]]\ncentre = [0.55, 0.45]\nradius = 0.22\n\n"
    "[fibre]\nE = 100.0\nnu = 0.2\n\n[matrix]\nE = 1.0\nnu = 0.35\n\n"
    "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n\n"
    "[load]\nboundary = \"periodic\"\n\n"
    "[sweep]\ndirections_deg = [0, 90]\nmagnitudes = [0.05, 0.1, 0.2, 0.3]\n\n"
    "[solver]\ntolerance = 1e-10\nsubdomain_dofs = 300\n";

class RveStages : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = dir_.write("s.toml", rve_text);
    mesh_ = dir_ / "mesh.h5";
    const auto m = run_command(bin("dualcell-mesh") + " --quiet --config " + q(scene_) + " --out " + q(mesh_));
    ASSERT_EQ(m.exit_code, exit_ok) << m.output;
  }
  std::string sweep_command(const std::string& launcher, const std::string& out) const {
    return launcher + bin("dualcell-sweep") + " --quiet --threads 1 --config " + q(scene_) + " --mesh " + q(mesh_) +
           " --out " + q(dir_ / out);
  }
  testing::ScratchDir dir_;
  std::filesystem::path scene_, mesh_;
};

// Past the fuse: each path's jump is bracketed, and the exact law (the RVE condensed onto its
// rims) replays every converged point along its path, the debond cascade included, to its QP
// limit with the same broken bonds: an independent solve of the same discrete problem. The fit
// makes no small cell (its ladder was 13 of the fit's 18 s here, and the law stage's tests fit
// small cells with a fuse): the flag leaves it out and says so.
TEST_F(RveStages, AdhesionThroughTheFuseIsReplayedByTheExactLaw) {
  const auto s = run_command(sweep_command("", "sweep.h5"));
  ASSERT_EQ(s.exit_code, exit_ok) << s.output;
  const auto f = run_command(bin("dualcell-fit") + " --quiet --no-small-cell --sweep " + q(dir_ / "sweep.h5") +
                             " --out " + q(dir_ / "law.h5"));
  ASSERT_EQ(f.exit_code, exit_ok) << f.output;
  const law::Law law = io::read_law(dir_ / "law.h5");
  EXPECT_FALSE(law.small.has_value());
  EXPECT_NE(law.small_note.find("--no-small-cell"), std::string::npos) << law.small_note;
  EXPECT_FALSE(law.cone_check.directions.empty()) << "the cone-wise law is still checked against the exact law";
  ASSERT_EQ(law.directions.size(), 2u);
  for (const auto& d : law.directions) {
    EXPECT_TRUE(std::isfinite(d.fuse_stress)) << d.direction_deg << ": no fuse within the sweep's loads";
    EXPECT_GT(d.fuse_strain_ratio, 1) << d.direction_deg << ": the strain jumps at the fuse";
  }
  ASSERT_TRUE(law.cell.has_value()) << law.cell_note;
  EXPECT_TRUE(law.cell.value().adhesion());
  EXPECT_TRUE(law.cell_replay.ok()) << law.cell_replay.max_error << " > " << law.cell_replay.limit;
  EXPECT_EQ(law.cell_replay.break_mismatches, 0);
  EXPECT_GT(law.cell_replay.points, 8);
  // The onset surface predicts the onset each path found by its own bracket (to the bracket's
  // fuse_tolerance, 1e-3 relative).
  ASSERT_TRUE(law.onset.linear);
  for (std::size_t i = 0; i < law.onset.path_onset.size(); ++i) {
    if (!std::isfinite(law.onset.path_sweep_onset[i])) continue;
    EXPECT_NEAR(law.onset.path_onset[i], law.onset.path_sweep_onset[i], 2e-3 * law.onset.path_onset[i]) << i;
  }
}

// Paths over 2 ranks (one path each), and both ranks on one path's subdomains: the serial
// sweep.h5. Two paths through the fuse (onsets 0.014 and 0.040), each loaded once to 0.05 with
// the jump bracketed to 1 %: the cascade's rounds and the bracket's bisections are the steps the
// ranks must repeat: 23 steps, 3.6 s serial in the release build, where the one path loaded to
// 0.1 and 0.3 before took 43 steps and 7.9 s (the sanitizer build runs this too, within
// mpiexec's 300 s).
TEST_F(RveStages, RanksWriteTheSerialSweep) {
  if (!testing::mpi_runs()) GTEST_SKIP() << "built without MPI or no mpiexec";
  std::string text = rve_text;
  const std::string sweep = "magnitudes = [0.05, 0.1, 0.2, 0.3]\n";
  text.replace(text.find(sweep), sweep.size(), "magnitudes = [0.05]\nfuse_tolerance = 0.01\n");
  scene_ = dir_.write("s.toml", text);
  ASSERT_EQ(run_command(sweep_command("", "serial.h5")).exit_code, exit_ok);
  const auto paths = run_command(sweep_command(testing::mpiexec(2), "paths.h5"));
  ASSERT_EQ(paths.exit_code, exit_ok) << paths.output;
  const std::vector<sweep::PathResult> serial = io::read_sweep(dir_ / "serial.h5");
  ASSERT_EQ(serial.size(), 2u);
  for (const sweep::PathResult& p : serial) EXPECT_TRUE(p.fuse.has_value()) << "every path passes its fuse";
  EXPECT_EQ(testing::h5diff_except(dir_ / "serial.h5", dir_ / "paths.h5", {"/seconds>"}), "");
  const auto group =
      run_command(testing::mpiexec(2) + bin("dualcell-sweep") + " --quiet --threads 1 --ranks-per-path 2 --config " +
                  q(scene_) + " --mesh " + q(mesh_) + " --out " + q(dir_ / "group.h5"));
  ASSERT_EQ(group.exit_code, exit_ok) << group.output;
  EXPECT_EQ(testing::h5diff_except(dir_ / "serial.h5", dir_ / "group.h5", {"/seconds>"}), "");
}

}  // namespace
}  // namespace dualcell
