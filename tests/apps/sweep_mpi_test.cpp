// dualcell-sweep under mpiexec (1, 2, 3 ranks, oversubscribed on this 2-core machine): the
// paths are handed out to the ranks, or to groups of ranks that share one path's subdomains,
// and rank 0 writes sweep.h5, which must equal the serial one bit for bit but for the seconds
// columns; killing one rank dead and running again resumes
// from the journal to the same file; a bad input stops every rank with one message and exit 1;
// a stage that does not share its work runs once.
// Skipped in a build without MPI or without mpiexec.
#include <gtest/gtest.h>

#include "core/exit_codes.hpp"
#include "par/parallel.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;
using testing::mpiexec;
using testing::run_command;

class SweepMpi : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!par::built_with_mpi()) GTEST_SKIP() << "built without MPI";
    if (run_command("command -v mpiexec").exit_code != 0) GTEST_SKIP() << "no mpiexec";
    // Adhesion, so that the paths differ in cost (fuse brackets) and in number of steps.
    scene_ =
        dir_.write("s.toml", testing::scene_text(2, 1, 1, 0.3,
                                                 "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n"
                                                 "[load]\nboundary = \"periodic\"\n[sweep]\n"
                                                 "directions_deg = [0, 30, 60, 90]\nsphere = 6\n"
                                                 "magnitudes = [-1.0, -0.5, 0.5, 1.0]\n"));
    mesh_ = dir_ / "mesh.h5";
    ASSERT_EQ(run_command(bin("dualcell-mesh") + " --quiet --config " + scene_.string() + " --out " + mesh_.string())
                  .exit_code,
              0);
    const auto serial = run_command(sweep_command("") + (dir_ / "serial.h5").string());
    ASSERT_EQ(serial.exit_code, 0) << serial.output;
  }
  std::string sweep_command(const std::string& launcher) const {
    return launcher + bin("dualcell-sweep") + " --quiet --threads 1 --config " + scene_.string() + " --mesh " +
           mesh_.string() + " --out ";
  }
  // Every difference from the serial file must be a /paths/NNN/seconds dataset.
  std::string differences_but_seconds(const std::string& file) const {
    return testing::h5diff_except(dir_ / "serial.h5", dir_ / file, {"/seconds>"});
  }
  testing::ScratchDir dir_;
  std::filesystem::path scene_, mesh_;
};

TEST_F(SweepMpi, AnyNumberOfRanksWritesTheSerialSweep) {
  for (int ranks : {1, 2, 3}) {
    const std::string out = std::to_string(ranks) + "-ranks.h5";
    const auto r = run_command(sweep_command(mpiexec(ranks)) + (dir_ / out).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(differences_but_seconds(out), "") << ranks << " ranks";
  }
}

// Paths solved by groups of ranks sharing the subdomains (--ranks-per-path 2 on 3 ranks: a
// group of two and a single rank) give the serial file too: rows of B couple at most two
// subdomains (the macro subdomain of the periodic boundary adds exact zeros), so the ranks' row
// sums, added in rank order, are the serial sums bit for bit.
TEST_F(SweepMpi, GroupsOfRanksSharingAPathWriteTheSerialSweep) {
  const auto r = run_command(sweep_command(mpiexec(3)) + (dir_ / "grouped.h5").string() + " --ranks-per-path 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(differences_but_seconds("grouped.h5"), "");
}

TEST_F(SweepMpi, KillingOneRankAndRunningAgainResumesToTheSameSweep) {
  const std::string out = (dir_ / "killed.h5").string();
  // The last of three ranks gets SIGKILL (kill -9) after its first path; mpiexec stops the rest.
  const auto killed = run_command(sweep_command(mpiexec(3)) + out + " --interrupt-after-paths 1");
  EXPECT_NE(killed.exit_code, 0) << killed.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  const auto again = run_command(sweep_command(mpiexec(2)) + out);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(differences_but_seconds("killed.h5"), "");
}

// An error that one rank meets alone in the middle of the sweep stops every rank with its
// message, instead of leaving the others waiting for it for ever. Here the leader of a group
// of two cannot journal its first path (the journal's folder is taken by a file): its partner
// waits for it inside the path hand-out, and it must not wait in turn for the others to free
// the hand-out's shared counter (a collective) on its way to stopping them all.
TEST_F(SweepMpi, AnErrorOfOneRankInTheMiddleStopsEveryRank) {
  const auto out = dir_ / "blocked.h5";
  dir_.write("blocked.h5.parts", "a file where the journal's folder goes\n");
  const auto r = run_command(mpiexec(3, 60) + sweep_command("") + out.string() + " --ranks-per-path 2");
  EXPECT_NE(r.exit_code, 124) << "a rank waited for ever:\n" << r.output;
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("blocked.h5.parts"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A stage that does not share its work (here dualcell-mesh) runs once under mpiexec, on rank
// 0: one summary, the file the serial run writes; its input errors are reported once too.
TEST_F(SweepMpi, AStageThatDoesNotShareRunsOnceOnRankZero) {
  const auto r = run_command(mpiexec(3) + bin("dualcell-mesh") + " --config " + scene_.string() + " --out " +
                             (dir_ / "mesh-3.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(testing::occurrences(r.output, "dualcell-mesh: "), 1u) << r.output;
  EXPECT_EQ(testing::h5diff_except(mesh_, dir_ / "mesh-3.h5", {}), "");
  const auto bad = run_command(mpiexec(3) + bin("dualcell-mesh") + " --config " + (dir_ / "absent.toml").string() +
                               " --out " + (dir_ / "x.h5").string());
  EXPECT_EQ(bad.exit_code, exit_input_error) << bad.output;
  EXPECT_EQ(testing::occurrences(bad.output, "dualcell-mesh: error:"), 1u) << bad.output;
}

TEST_F(SweepMpi, BadInputStopsEveryRankWithOneMessage) {
  const auto r = run_command(mpiexec(3) + bin("dualcell-sweep") + " --quiet --config " + scene_.string() + " --mesh " +
                             (dir_ / "absent.h5").string() + " --out " + (dir_ / "x.h5").string());
  EXPECT_EQ(r.exit_code, exit_input_error) << r.output;
  EXPECT_EQ(testing::occurrences(r.output, "dualcell-sweep: error:"), 1u) << r.output;
  EXPECT_NE(r.output.find("absent.h5"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.h5"));
}

}  // namespace
}  // namespace dualcell
