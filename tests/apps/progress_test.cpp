// A long solve says how it is doing (docs/guide/solve.md, "Progress"): on a terminal one line rewritten in
// place and erased before the summary; in a pipe plain lines at most one per interval (none for a
// short run at the default 5 s); nothing with --quiet; under mpirun from rank 0 alone.
#include <gtest/gtest.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;

// Runs `command` (through sh) with stdin, stdout and stderr on a new pseudo-terminal and returns
// everything it wrote there (the terminal turns "\n" into "\r\n").
std::string run_on_terminal(const std::string& command) {
  int master = -1;
  const pid_t pid = ::forkpty(&master, nullptr, nullptr, nullptr);
  if (pid < 0) return "forkpty failed";
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::string output;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(master, buffer, sizeof buffer);
    if (n <= 0) break;  // EIO once the child has closed the terminal
    output.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(master);
  ::waitpid(pid, nullptr, 0);
  return output;
}

// `command`'s stderr alone (stdout discarded) and its exit code.
testing::CommandResult stderr_of(const std::string& command) {
  return testing::run_command("{ " + command + " 2>&1 >/dev/null; }");
}

class Progress : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto scene = dir_.write("s.toml", testing::scene_text(2, 2, 3, 0.3, "[load]\nboundary = \"periodic\"\n"));
    ASSERT_EQ(testing::run_command(bin("dualcell-mesh") + " --quiet --config " + scene.string() + " --out " +
                                   (dir_ / "mesh.h5").string())
                  .exit_code,
              0);
    solve_ = bin("dualcell-solve") + " --config " + scene.string() + " --mesh " + (dir_ / "mesh.h5").string() +
             " --stress -1,0.2,0 --out " + (dir_ / "sol.h5").string();
  }
  testing::ScratchDir dir_;
  std::string solve_;
};

TEST_F(Progress, OnATerminalOneLineInPlaceErasedBeforeTheSummary) {
  const std::string out = run_on_terminal("TERM=xterm " + solve_);
  // The state, rewritten in place: a return, the stage, the text, erase to the end of the line.
  EXPECT_NE(out.find("\rdualcell-solve: assembly"), std::string::npos) << out;
  EXPECT_NE(out.find("\x1b[K"), std::string::npos) << out;
  // Erased before the summary, which starts on a clean line.
  const std::size_t summary = out.find("dualcell-solve: " + dir_.path().string());
  ASSERT_NE(summary, std::string::npos) << out;
  ASSERT_GE(summary, 4u);
  EXPECT_EQ(out.substr(summary - 4, 4), "\r\x1b[K") << out;
  EXPECT_EQ(out.find("\x1b", summary), std::string::npos) << "progress after the summary: " << out;
}

TEST_F(Progress, QuietPrintsNothingOnATerminal) { EXPECT_EQ(run_on_terminal("TERM=xterm " + solve_ + " --quiet"), ""); }

TEST_F(Progress, InAPipePlainLinesAtMostOnePerInterval) {
  // A solve shorter than the interval (an hour here, so that no slow machine or sanitizer build
  // outlasts it): no progress line at all, only the summary.
  const auto quiet_log = stderr_of("DUALCELL_PROGRESS_INTERVAL=3600 " + solve_);
  EXPECT_EQ(quiet_log.output, "");
  // At an interval of 0 every due update is a plain line: no returns, no escapes.
  const auto log = stderr_of("DUALCELL_PROGRESS_INTERVAL=0 " + solve_);
  EXPECT_EQ(log.exit_code, 0);
  EXPECT_NE(log.output.find("dualcell-solve: assembly"), std::string::npos) << log.output;
  EXPECT_NE(log.output.find("dualcell-solve: QP ("), std::string::npos) << log.output;
  EXPECT_NE(log.output.find("F applications"), std::string::npos) << log.output;
  EXPECT_EQ(log.output.find('\r'), std::string::npos) << log.output;
  EXPECT_EQ(log.output.find('\x1b'), std::string::npos) << log.output;
  ASSERT_FALSE(log.output.empty());
  EXPECT_EQ(log.output.back(), '\n');
  // An interval that is not a number of seconds is said, not ignored without a word.
  const auto bad = stderr_of("DUALCELL_PROGRESS_INTERVAL=soon " + solve_);
  EXPECT_EQ(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("warning: DUALCELL_PROGRESS_INTERVAL = 'soon' is not a number of seconds >= 0: 5 s used"),
            std::string::npos)
      << bad.output;
}

// A long fit says how far it is as the sweep does (a 10-fibre RVE's ran over 3 minutes silent):
// dualcell-fit passes its Progress down (the sampling of the exact law here; the small cell's
// ladder in SmallCell.IsAConvexCellThatBeatsItsStartAndHoldsOnOtherDirections), a plain line per
// due update in a pipe; nothing with --quiet.
TEST(FitProgress, TheFitShowsTheSamplingOfTheExactLaw) {
  testing::ScratchDir dir;
  const auto scene = dir.write("s.toml", testing::scene_text(1, 1, 2, 0.3,
                                                             "[load]\nboundary = \"periodic\"\n[sweep]\n"
                                                             "directions_deg = [0, 90]\nmagnitudes = [-0.1, 0.1]\n"));
  const std::string cfg = " --quiet --config " + scene.string() + " --mesh " + (dir / "mesh.h5").string();
  ASSERT_EQ(testing::run_command(bin("dualcell-mesh") + " --quiet --config " + scene.string() + " --out " +
                                 (dir / "mesh.h5").string())
                .exit_code,
            0);
  const auto sweep = testing::run_command(bin("dualcell-sweep") + cfg + " --out " + (dir / "sweep.h5").string());
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  const std::string fit =
      bin("dualcell-fit") + " --sweep " + (dir / "sweep.h5").string() + " --out " + (dir / "law.h5").string();
  const auto log = stderr_of("DUALCELL_PROGRESS_INTERVAL=0 " + fit);
  EXPECT_EQ(log.exit_code, 0) << log.output;
  EXPECT_NE(log.output.find("dualcell-fit: sampling the exact law below the onset: direction "), std::string::npos)
      << log.output.substr(0, 2000);
  EXPECT_EQ(log.output.find('\r'), std::string::npos);
  const auto quiet = stderr_of("DUALCELL_PROGRESS_INTERVAL=0 " + fit + " --quiet");
  EXPECT_EQ(quiet.exit_code, 0);
  EXPECT_EQ(quiet.output, "");
}

TEST_F(Progress, UnderMpirunOnlyRankZeroPrints) {
  if (!testing::mpi_runs()) GTEST_SKIP() << "built without MPI, or no mpiexec";
  const auto log = stderr_of("DUALCELL_PROGRESS_INTERVAL=0 " + testing::mpiexec(2, 120) + solve_);
  EXPECT_EQ(log.exit_code, 0) << log.output;
  EXPECT_EQ(testing::occurrences(log.output, "dualcell-solve: assembly"), 1u) << log.output;
}

}  // namespace
}  // namespace dualcell
