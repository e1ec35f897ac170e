// The solver refuses a scene built in code with an out-of-range value, with the message a scene
// file would get (validate() in core/scene.hpp), before any assembly; it spreads subdomain work
// over threads exactly when there are enough DOFs for each.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "feti/solver.hpp"
#include "mesh/mesh.hpp"
#include "test_util.hpp"

namespace dualcell::feti {
namespace {

TEST(FetiSetup, ValidatesScenesBuiltInCode) {
  Scene scene = parse_scene(testing::scene_text(1, 1, 1, 0.3), "scene.toml");
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  scene.written.clear();
  scene.file.clear();
  scene.fibre.E = -1;
  try {
    ContactSolver solver(mesh, scene);
    FAIL() << "a negative Young's modulus was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "scene: [fibre] E = -1: out of range: E > 0");
  }
}

// Threads share the subdomains once each thread gets min_dofs_per_thread DOFs: the threshold
// is met exactly at dim u / threads (one rank owns every subdomain here).
TEST(FetiSetup, UsesThreadsFromTheThresholdOn) {
  const Scene scene = parse_scene(testing::scene_text(2, 2, 2, 0.3), "scene.toml");
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  const int per_thread = mesh.dim_u() / 2;
  ASSERT_GT(per_thread, 100);
  EXPECT_TRUE(ContactSolver(mesh, scene, 2, per_thread).setup().parallel());
  EXPECT_FALSE(ContactSolver(mesh, scene, 2, per_thread + 1).setup().parallel());
  EXPECT_FALSE(ContactSolver(mesh, scene, 1, 0).setup().parallel());
}

}  // namespace
}  // namespace dualcell::feti
