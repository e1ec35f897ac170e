// The figures the README's quick start quotes from the default scene's run are checked against a
// fresh run of that scene (mesh → sweep → fit, about 10 s): the lines the README shows as the
// sweep's and the fit's output must be what the stages print today, so that a change of the cell, the law or its
// check cannot leave the README quoting an older run. Counts (interface rows, kB, points,
// directions) and the printed percentages must agree exactly; the replay error is round-off
// (a few 1e-8 on this cell), whose digits differ between machines and builds, so it must stay
// within a factor 3 of the quoted value, still far below its limit of 1e-5.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/law_file.hpp"
#include "law/fused_cell.hpp"
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

// The numbers of the first line of `text` that starts with `prefix` (anywhere in the text),
// read by sscanf with `format` (which starts after the prefix); empty, and the test failed,
// when there is none or it does not parse. (No std::regex: GCC 12 warns inside it under the
// sanitizers, and the build treats warnings as errors.)
std::vector<double> numbers_after(const std::string& text, const std::string& prefix, const char* format, int count,
                                  const std::string& what) {
  const std::size_t at = text.find(prefix);
  EXPECT_NE(at, std::string::npos) << what << ": no '" << prefix << "'";
  if (at == std::string::npos) return {};
  const std::string line = text.substr(at + prefix.size(), text.find('\n', at) - at - prefix.size());
  double v[5] = {0, 0, 0, 0, 0};
  const int read = std::sscanf(line.c_str(), format, &v[0], &v[1], &v[2], &v[3], &v[4]);
  EXPECT_EQ(read, count) << what << ": '" << prefix << line << "'";
  if (read != count) return {};
  return std::vector<double>(v, v + count);
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

  const std::string condensed = "exact law: the cell condensed onto ";
  const char* condensed_format = "%lf interface rows, %lf kB";
  EXPECT_EQ(numbers_after(text, condensed, condensed_format, 2, "README"),
            numbers_after(sweep.output, condensed, condensed_format, 2, "dualcell-sweep"))
      << "interface rows, kB";

  const std::string replay = "exact law: the cell on ";
  const char* replay_format = "%lf interface rows; replays the sweep's %lf points to max %lf, rms %lf (limit %lf)";
  const std::vector<double> quoted = numbers_after(text, replay, replay_format, 5, "README");
  const std::vector<double> run = numbers_after(fit.output, replay, replay_format, 5, "dualcell-fit");
  ASSERT_EQ(quoted.size(), 5u);
  ASSERT_EQ(run.size(), 5u);
  EXPECT_EQ(quoted[0], run[0]) << "rows";
  EXPECT_EQ(quoted[1], run[1]) << "points";
  EXPECT_EQ(quoted[4], run[4]) << "limit";
  EXPECT_LE(run[2], 3 * quoted[2]) << "replay max";
  EXPECT_GE(run[2], quoted[2] / 3) << "replay max";

  const std::string cone = "cone-wise law against the exact law at ";
  const char* cone_format = "%lf stress directions: stress error max %lf";
  EXPECT_EQ(numbers_after(text, cone, cone_format, 2, "README"),
            numbers_after(fit.output, cone, cone_format, 2, "dualcell-fit"))
      << "directions, max";
  const std::string rms = "), rms ";
  EXPECT_EQ(numbers_after(text.substr(text.find(cone)), rms, "%lf", 1, "README"),
            numbers_after(fit.output.substr(fit.output.find(cone)), rms, "%lf", 1, "dualcell-fit"))
      << "rms";

  // The small cell with a fuse (docs/method.md §16d): its rows and its error along the exact law's
  // cascade paths, as quoted (the worst direction is left out: the cell's symmetric directions
  // tie, and round-off picks one).
  const std::string fused = "small cell with a fuse: bonded, the exact bonded law and onset (";
  const char* fused_format = "%lf facet rows); past the fuse %lf rows";
  EXPECT_EQ(numbers_after(text, fused, fused_format, 2, "README"),
            numbers_after(fit.output, fused, fused_format, 2, "dualcell-fit"))
      << "facet rows, rows past the fuse";
  const std::string along = "other directions' paths (9 points each): max ";
  EXPECT_EQ(numbers_after(text, along, "%lf", 1, "README"), numbers_after(fit.output, along, "%lf", 1, "dualcell-fit"))
      << "max along the cascade paths";
  EXPECT_EQ(numbers_after(text.substr(text.find(along)), rms, "%lf", 1, "README"),
            numbers_after(fit.output.substr(fit.output.find(along)), rms, "%lf", 1, "dualcell-fit"))
      << "rms along the cascade paths";
  // What law.h5 records is what its two cells give: the check recomputed from the file's exact
  // law and small cell (the same directions and paths, the same evaluator: to round-off).
  const law::Law law = io::read_law(dir / "law.h5");
  ASSERT_TRUE(law.cell && law.small) << law.small_note;
  EXPECT_EQ(law.small_check.against, law::CheckedAgainst::exact_law_past_fuse);
  constexpr int past_fuse_check_directions = 300;  // the fit's (src/fit/fit.cpp)
  const law::ConeCheck again = law::check_along_fuse_paths(
      *law.small, law::sample_cell_past_fuse(*law.cell, past_fuse_check_directions, law::past_fuse_load_ratio));
  EXPECT_EQ(again.directions.size(), law.small_check.directions.size());
  EXPECT_NEAR(again.max_error, law.small_check.max_error, 1e-9);
  EXPECT_NEAR(again.rms_error, law.small_check.rms_error, 1e-9);
}

}  // namespace
}  // namespace dualcell
