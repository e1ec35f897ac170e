// dualcell-mesh as a user runs it: help, summary, and bad input answered with one line, a
// non-zero exit and no output file.
#include <gtest/gtest.h>

#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;
using testing::run_command;

TEST(MeshStage, HelpAndSummary) {
  auto r = run_command(bin("dualcell-mesh") + " --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("--config"), std::string::npos);
  testing::ScratchDir dir;
  // The thesis' counts: 3×3 cells of linear triangles at degree 1.
  const auto scene = dir.write("s.toml", testing::scene_text(3, 3, 1, 0.3, "", "p1"));
  r = run_command(bin("dualcell-mesh") + " --config " + scene.string() + " --out " + (dir / "m.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* line : {"cells            3 x 3", "subdomains       18", "nodes            297",
                           "interface pairs  72", "glue pairs       56", "dim u            594", "minimum angle"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
}

TEST(MeshStage, BadInputGivesOneLineNonZeroExitAndNoOutput) {
  testing::ScratchDir dir;
  struct Case {
    std::string scene, out, expected;
  };
  const std::string out = (dir / "m.h5").string();
  const std::vector<Case> cases = {
      {testing::scene_text(1, 1, 1, -0.2), out, "fibre_radius = -0.2"},
      {testing::scene_text(1, 1, 1, 0.55), out, "touches or crosses"},
      {testing::scene_text(1, 1, 0, 0.3), out, "degree = 0"},
      {testing::scene_text(0, 1, 1, 0.3), out, "cells"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 1\nnu = 0.7\n[matrix]\nE = 1\nnu = 0.3\n", out, "nu = 0.7"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = -1\nnu = 0.2\n[matrix]\nE = 1\nnu = 0.3\n", out, "E = -1"},
      {testing::scene_text(1, 1, 1, 0.3, "[solver]\nfoo = 1\n"), out, "unknown key"},
      {testing::scene_text(1, 1, 1, 0.3), "/proc/version/m.h5", "cannot write output"},
      {testing::scene_text(1, 1, 1, 0.3), (dir / "no/such/dir/m.h5").string(), "does not exist"},
  };
  for (const auto& c : cases) {
    const auto scene = dir.write("s.toml", c.scene);
    const auto r = run_command(bin("dualcell-mesh") + " --config " + scene.string() + " --out " + c.out);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
    EXPECT_EQ(r.output.rfind("dualcell-mesh: error: ", 0), 0u) << r.output;
    EXPECT_FALSE(std::filesystem::exists(c.out)) << c.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "m.xdmf"));
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
      EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << "temporary left: " << e.path();
  }
  const auto r = run_command(bin("dualcell-mesh") + " --config " + (dir / "absent.toml").string() + " --out " + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("absent.toml: scene file not found"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace dualcell
