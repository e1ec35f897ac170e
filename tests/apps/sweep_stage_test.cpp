// dualcell-sweep as a user runs it: the documented layout, resume after a hard stop with the
// same data as an uninterrupted run, and refusals that leave no output.
#include <gtest/gtest.h>

#include "core/exit_codes.hpp"
#include "io/hdf5.hpp"
#include "io/sweep_file.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;
using testing::run_command;

std::filesystem::path make_mesh(const testing::ScratchDir& dir, const std::string& scene_text) {
  const auto scene = dir.write("s.toml", scene_text);
  const auto r = run_command(bin("dualcell-mesh") + " --quiet --config " + scene.string() + " --out " +
                             (dir / "mesh.h5").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return scene;
}

std::string sweep_command(const std::filesystem::path& scene, const testing::ScratchDir& dir, const std::string& out) {
  return bin("dualcell-sweep") + " --quiet --config " + scene.string() + " --mesh " + (dir / "mesh.h5").string() +
         " --out " + (dir / out).string();
}

const std::string paths_scene = testing::scene_text(
    2, 1, 2, 0.3,
    "[load]\nboundary = \"traction\"\n[sweep]\ndirections_deg = [0, 30, 90]\nmagnitudes = [-2, -1, 1, 2]\n");

TEST(SweepStage, WritesTheDocumentedLayoutWithAFuse) {
  testing::ScratchDir dir;
  const auto scene =
      make_mesh(dir, testing::scene_text(1, 1, 1, 0.4,
                                         "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n"
                                         "[load]\nboundary = \"traction\"\n"
                                         "[sweep]\ndirections_deg = [0]\nmagnitudes = [0.05, 0.2]\n"));
  const auto r = run_command(sweep_command(scene, dir, "sweep.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  io::File f = io::File::open_read(dir / "sweep.h5");
  for (const char* name :
       {"load", "stress", "strain", "broken_bonds", "outer_iterations", "operator_applications", "kkt_residual",
        "seconds", "fuse/onset_load", "fuse/load_before", "fuse/load_after", "fuse/strain_before", "fuse/strain_after"})
    EXPECT_TRUE(f.exists(std::string("/paths/000/") + name)) << name;
  EXPECT_EQ(f.read_int_attribute("/paths/000", "sign")[0], 1);
  EXPECT_EQ(f.read_double_attribute("/paths/000", "direction_deg")[0], 0.0);
  for (const char* attr : {"scene", "mesh_hash", "solver_options", "code_version"})
    EXPECT_TRUE(f.has_attribute("/", attr)) << attr;
  EXPECT_EQ(f.shape("/paths/000/strain")[1], 3u);
  EXPECT_FALSE(std::filesystem::exists(dir / "sweep.h5.parts"));
}

// Steps whose QP stopped short (here at an application limit no contact solve meets) are
// written and marked, and the stage says so: exit 4, as every stage that ran without converging.
TEST(SweepStage, UnconvergedStepsAreWrittenMarkedAndExitFour) {
  testing::ScratchDir dir;
  const auto scene = make_mesh(dir, testing::scene_text(1, 1, 2, 0.3,
                                                        "[solver]\nmax_operator_applications = 3\n"
                                                        "[load]\nboundary = \"traction\"\n"
                                                        "[sweep]\ndirections_deg = [0]\nmagnitudes = [1]\n"));
  const auto r = run_command(sweep_command(scene, dir, "sweep.h5"));
  EXPECT_EQ(r.exit_code, exit_not_converged) << r.output;
  EXPECT_NE(r.output.find("did not converge"), std::string::npos) << r.output;
  io::File f = io::File::open_read(dir / "sweep.h5");
  const auto converged = f.read_ints("/paths/000/converged", {io::any_extent});
  ASSERT_FALSE(converged.empty());
  EXPECT_EQ(converged.back(), 0);
}

// The uniaxial paths of a sweep with [sweep] sphere are those of the same sweep without it:
// the same schedule, bond history and numbers, bit for bit (each path starts from the intact,
// unloaded state with the cached dual problem dropped), with and without adhesion; the sphere
// paths follow them.
TEST(SweepStage, UniaxialPathsAreTheSameWithTheSphere) {
  for (const std::string interface : {"", "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n"}) {
    testing::ScratchDir dir;
    const std::string sweep = "[sweep]\ndirections_deg = [0, 45]\nmagnitudes = [-0.2, -0.05, 0.05, 0.2]\n";
    const auto plain =
        make_mesh(dir, testing::scene_text(1, 1, 1, 0.4, interface + "[load]\nboundary = \"periodic\"\n" + sweep));
    const auto sphere = dir.write(
        "sphere.toml",
        testing::scene_text(1, 1, 1, 0.4, interface + "[load]\nboundary = \"periodic\"\n" + sweep + "sphere = 6\n"));
    ASSERT_EQ(run_command(sweep_command(plain, dir, "plain.h5")).exit_code, 0);
    const auto r = run_command(sweep_command(sphere, dir, "sphere.h5"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto a = io::read_sweep(dir / "plain.h5"), b = io::read_sweep(dir / "sphere.h5");
    ASSERT_EQ(b.size(), a.size() + 6);
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k].steps.size(), b[k].steps.size()) << "path " << k;
      for (std::size_t i = 0; i < a[k].steps.size(); ++i) {
        EXPECT_EQ(a[k].steps[i].load, b[k].steps[i].load) << "path " << k << " step " << i;
        EXPECT_EQ(a[k].steps[i].strain, b[k].steps[i].strain) << "path " << k << " step " << i;
        EXPECT_EQ(a[k].steps[i].broken_bonds, b[k].steps[i].broken_bonds) << "path " << k << " step " << i;
      }
      EXPECT_EQ(a[k].fuse.has_value(), b[k].fuse.has_value()) << "path " << k;
    }
    for (std::size_t k = a.size(); k < b.size(); ++k) EXPECT_TRUE(b[k].spec.sphere) << "path " << k;
  }
}

TEST(SweepStage, ResumesAfterAHardStopWithIdenticalData) {
  testing::ScratchDir dir;
  const auto scene = make_mesh(dir, paths_scene);
  ASSERT_EQ(run_command(sweep_command(scene, dir, "whole.h5")).exit_code, 0);
  // SIGKILL (kill -9) after two finished paths: no final file, two parts.
  const auto stopped = run_command(sweep_command(scene, dir, "resumed.h5") + " --interrupt-after-paths 2");
  EXPECT_EQ(stopped.exit_code, 137) << stopped.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "resumed.h5"));
  int parts = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir / "resumed.h5.parts")) ++parts;
  EXPECT_EQ(parts, 2);
  ASSERT_EQ(run_command(sweep_command(scene, dir, "resumed.h5")).exit_code, 0);
  const auto whole = io::read_sweep(dir / "whole.h5"), resumed = io::read_sweep(dir / "resumed.h5");
  ASSERT_EQ(whole.size(), 6u);
  ASSERT_EQ(resumed.size(), whole.size());
  for (std::size_t p = 0; p < whole.size(); ++p) {
    ASSERT_EQ(resumed[p].steps.size(), whole[p].steps.size());
    EXPECT_EQ(resumed[p].spec.state.value, whole[p].spec.state.value);
    for (std::size_t i = 0; i < whole[p].steps.size(); ++i) {
      const auto &a = whole[p].steps[i], &b = resumed[p].steps[i];
      // Everything but the wall time is bitwise identical.
      EXPECT_EQ(a.load, b.load);
      EXPECT_EQ(a.stress, b.stress);
      EXPECT_EQ(a.strain, b.strain);
      EXPECT_EQ(a.broken_bonds, b.broken_bonds);
      EXPECT_EQ(a.outer_iterations, b.outer_iterations);
      EXPECT_EQ(a.operator_applications, b.operator_applications);
      EXPECT_EQ(a.kkt_residual, b.kkt_residual);
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "resumed.h5.parts"));
}

TEST(SweepStage, RefusesAForeignMeshAndDirectionsTheBoundaryCannotCarry) {
  testing::ScratchDir dir;
  const auto scene = make_mesh(dir, paths_scene);
  const auto other = dir.write("other.toml", testing::scene_text(2, 1, 2, 0.25, "[load]\nboundary = \"traction\"\n"));
  auto r = run_command(sweep_command(other, dir, "sweep.h5"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("[geometry] fibre_radius: mesh 0.3, scene 0.25"), std::string::npos) << r.output;
  const auto symmetric =
      dir.write("sym.toml", testing::scene_text(2, 1, 2, 0.3, "[sweep]\ndirections_deg = [0, 45]\n"));
  r = run_command(sweep_command(symmetric, dir, "sweep.h5"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("the symmetry boundary carries only shear-free directions"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "sweep.h5"));
  EXPECT_FALSE(std::filesystem::exists(dir / "sweep.h5.parts"));
}

}  // namespace
}  // namespace dualcell
