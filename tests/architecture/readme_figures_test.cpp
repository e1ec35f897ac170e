// The figures the README quotes from the default scene's run are checked against a fresh run of
// that scene (mesh → sweep → fit, about 10 s): the lines the README shows as the sweep's and the
// fit's output must be what the stages print today, so that a change of the cell, the law or its
// check cannot leave the README quoting an older run. Counts (interface rows, kB, points,
// directions) and the printed percentages must agree exactly; the replay error is round-off
// (a few 1e-8 on this cell), whose digits differ between machines and builds, so it must stay
// within a factor 3 of the quoted value, still far below its limit of 1e-5.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;
using testing::run_command;

std::string readme() {
  std::ifstream in(testing::source_dir() + "/README.md");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The groups of the first match of `pattern` in `text` (empty strings, and the test failed,
// when nothing matches).
std::vector<std::string> first_match(const std::string& text, const std::string& pattern, const std::string& what) {
  std::smatch m;
  const bool found = std::regex_search(text, m, std::regex(pattern));
  EXPECT_TRUE(found) << what << ": no line matches " << pattern;
  std::vector<std::string> groups(8);
  if (found)
    for (std::size_t k = 0; k < m.size() && k < groups.size(); ++k) groups[k] = m[k];
  return groups;
}

TEST(Readme, TheDefaultScenesQuotedFiguresHoldOnAFreshRun) {
  testing::ScratchDir dir;
  const std::string scene = testing::source_dir() + "/pipelines/scenes/default.toml";
  const auto mesh =
      run_command(bin("dualcell-mesh") + " --quiet --config " + scene + " --out " + (dir / "mesh.h5").string());
  ASSERT_EQ(mesh.exit_code, 0) << mesh.output;
  const auto sweep = run_command(bin("dualcell-sweep") + " --config " + scene + " --mesh " +
                                 (dir / "mesh.h5").string() + " --out " + (dir / "sweep.h5").string());
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  const auto fit = run_command(bin("dualcell-fit") + " --sweep " + (dir / "sweep.h5").string() + " --out " +
                               (dir / "law.h5").string());
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  const std::string text = readme();

  const std::string condensed = R"(exact law: the cell condensed onto (\d+) interface rows, (\d+) kB)";
  const auto quoted_sweep = first_match(text, condensed, "README");
  const auto run_sweep = first_match(sweep.output, condensed, "dualcell-sweep");
  EXPECT_EQ(quoted_sweep[1], run_sweep[1]) << "interface rows";
  EXPECT_EQ(quoted_sweep[2], run_sweep[2]) << "kB";

  const std::string replay = R"(exact law: the cell on (\d+) interface rows; replays the sweep's (\d+) points to max )"
                             R"(([0-9.e+-]+), rms ([0-9.e+-]+) \(limit ([0-9.e+-]+)\), broken bonds the same)";
  const auto quoted_replay = first_match(text, replay, "README");
  const auto run_replay = first_match(fit.output, replay, "dualcell-fit");
  EXPECT_EQ(quoted_replay[1], run_replay[1]) << "rows";
  EXPECT_EQ(quoted_replay[2], run_replay[2]) << "points";
  EXPECT_EQ(quoted_replay[5], run_replay[5]) << "limit";
  const double quoted_max = std::stod(quoted_replay[3].empty() ? "0" : quoted_replay[3]),
               run_max = std::stod(run_replay[3].empty() ? "0" : run_replay[3]);
  EXPECT_LE(run_max, 3 * quoted_max);
  EXPECT_GE(run_max, quoted_max / 3);

  const std::string cone = R"(cone-wise law against the exact law at (\d+) stress directions: stress error max )"
                           R"(([0-9.]+) %.*, rms ([0-9.]+) %)";
  const auto quoted_cone = first_match(text, cone, "README");
  const auto run_cone = first_match(fit.output, cone, "dualcell-fit");
  for (int k : {1, 2, 3}) EXPECT_EQ(quoted_cone[k], run_cone[k]) << "cone check, group " << k;
}

}  // namespace
}  // namespace dualcell
