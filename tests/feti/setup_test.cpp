// The solver refuses a scene built in code with an out-of-range value, with the message a scene
// file would get (validate() in core/scene.hpp), before any assembly.
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

}  // namespace
}  // namespace dualcell::feti
