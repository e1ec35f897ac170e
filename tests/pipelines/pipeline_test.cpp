// The make-driven pipeline as a user runs it: a tiny scene through mesh → sweep → fit →
// exports → pictures, the law file checked, and a second make with nothing to do.
#include <gtest/gtest.h>

#include "io/law_file.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

TEST(Pipeline, TinySceneEndToEndThenNothingToDo) {
  testing::ScratchDir dir;
  std::filesystem::create_directories(dir / "scenes");
  // The material file of the scene, relative to it, like the committed scenes.
  std::filesystem::copy_file(testing::source_dir() + "/materials/glass-epoxy.toml", dir / "glass-epoxy.toml");
  dir.write("scenes/tiny.toml",
            "material = \"../glass-epoxy.toml\"\n[geometry]\ncells = [1, 1]\nfibre_radius = 0.35\ndegree = 1\n"
            "[load]\nboundary = \"periodic\"\n[sweep]\ndirections_deg = [0, 45, 90]\nmagnitudes = [-0.01, 0.01]\n");
  const std::string make = "make -C " + testing::source_dir() +
                           "/pipelines SCENE=tiny SCENES=" + (dir / "scenes").string() +
                           " OUT_ROOT=" + (dir / "out").string() + " BIN=" + DUALCELL_BIN_DIR + " BUILT=";
  const auto run = testing::run_command(make);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("results and pictures in"), std::string::npos) << run.output;
  const auto out = dir / "out" / "tiny";
  for (const char* file :
       {"mesh.h5", "mesh.xdmf", "sweep.h5", "law.h5", "law.json", "law.csv", "law.inp", "stress_strain.png",
        "stress_strain.svg", "polar.png", "polar.svg", "deformed.png", "deformed.svg", "index.txt", "exports.done"})
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  const law::Law law = io::read_law(out / "law.h5");
  ASSERT_EQ(law.directions.size(), 3u);
  for (const auto& d : law.directions) EXPECT_GT(d.E_compression / d.E_tension, 1.5) << d.direction_deg;
  EXPECT_EQ(law.tension.rank, 6);
  // Nothing left to do: make -n lists no command.
  const auto again = testing::run_command(make + " -n");
  EXPECT_EQ(again.exit_code, 0);
  EXPECT_NE(again.output.find("Nothing to be done"), std::string::npos) << again.output;
  // Touching the material re-runs the sweep (and what follows), not the mesh.
  std::filesystem::last_write_time(dir / "glass-epoxy.toml", std::filesystem::file_time_type::clock::now());
  const auto after_material = testing::run_command(make + " -n");
  EXPECT_NE(after_material.output.find("dualcell-sweep"), std::string::npos) << after_material.output;
  EXPECT_EQ(after_material.output.find("dualcell-mesh"), std::string::npos) << after_material.output;
}

}  // namespace
}  // namespace dualcell
