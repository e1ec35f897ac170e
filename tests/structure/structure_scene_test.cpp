// structure.toml: the documented keys are read, and every mistake is one line naming the file,
// the line, the key, the value and what is allowed.
#include "core/structure_scene.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace dualcell {
namespace {

const std::string beam =
    "[structure]\ncells = [16, 2]\nelements_per_cell = 3\nelement = \"p1\"\n"
    "[edges.left]\ntype = \"roller\"\n"
    "[edges.right]\ntype = \"traction\"\ntraction = [1e-3, 0]\ntraction_end = [-1e-3, 0]\n"
    "[edges.top]\ntype = \"displacement\"\nuy = -0.01\n"
    "[[support]]\nat = [0, 0]\nfix = \"y\"\n"
    "[[point_load]]\nat = [8, 2]\nforce = [0, -1e-4]\n"
    "[steps]\nfactors = [0.5, 1, 0.5]\n[output]\nwatch = [16, 0]\n[solver]\ntolerance = 1e-12\n";

TEST(StructureScene, ReadsTheDocumentedKeys) {
  const StructureScene s = parse_structure_scene(beam, "beam.toml");
  EXPECT_EQ(s.nx, 16);
  EXPECT_EQ(s.ny, 2);
  EXPECT_EQ(s.elements_per_cell, 3);
  EXPECT_EQ(s.element, Element::p1);
  EXPECT_EQ(s.quadrature, 6);
  EXPECT_EQ(
      parse_structure_scene(
          std::string("[structure]\ncells = [2, 2]\nquadrature = 3\n") + beam.substr(beam.find("[edges")), "q.toml")
          .quadrature,
      3);
  EXPECT_EQ(s.edges[0].kind, EdgeKind::roller);
  EXPECT_EQ(s.edges[1].kind, EdgeKind::traction);
  EXPECT_EQ(s.edges[1].traction_start, Eigen::Vector2d(1e-3, 0));
  EXPECT_EQ(s.edges[1].traction_end, Eigen::Vector2d(-1e-3, 0));
  EXPECT_EQ(s.edges[2].kind, EdgeKind::free);
  EXPECT_EQ(s.edges[3].kind, EdgeKind::displacement);
  EXPECT_TRUE(std::isnan(s.edges[3].displacement(0)));
  EXPECT_EQ(s.edges[3].displacement(1), -0.01);
  ASSERT_EQ(s.supports.size(), 1u);
  EXPECT_FALSE(s.supports[0].fix_x);
  EXPECT_TRUE(s.supports[0].fix_y);
  ASSERT_EQ(s.point_loads.size(), 1u);
  EXPECT_EQ(s.point_loads[0].force, Eigen::Vector2d(0, -1e-4));
  EXPECT_EQ(s.factors, (std::vector<double>{0.5, 1, 0.5}));
  EXPECT_EQ(s.watch, Eigen::Vector2d(16, 0));
  EXPECT_EQ(s.tolerance, 1e-12);
}

std::string refusal(const std::string& text) {
  try {
    parse_structure_scene(text, "s.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return "";
}

TEST(StructureScene, MistakesAreNamed) {
  const std::string held = "[edges.left]\ntype = \"fixed\"\n[edges.right]\ntype = \"traction\"\ntraction = [0, 1]\n";
  EXPECT_NE(refusal(held).find("s.toml: missing table [structure]"), std::string::npos);
  EXPECT_NE(refusal("[structure]\n" + held).find("[structure] cells: missing"), std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [0, 2]\n" + held).find("s.toml:2:9: [structure] cells"), std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\nelements_per_cell = 65\n" + held)
                .find("[structure] elements_per_cell = 65: must be an integer in [1, 64]"),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\nquadrature = 4\n" + held).find("quadrature = 4: must be 3 or 6"),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\nelement = \"p1\"\nquadrature = 3\n" + held)
                .find("a p1 triangle has one point"),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\nelement = \"p3\"\n" + held).find("must be one of \"p1\", \"p2\""),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\n[edges.middle]\ntype = \"fixed\"\n" + held)
                .find("[edges] middle: unknown edge"),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\n[edges.left]\ntype = \"glued\"\n")
                .find("[edges.left] type = \"glued\": must be one of \"free\", \"fixed\", \"roller\""),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\n[edges.left]\ntype = \"traction\"\n").find("traction: missing"),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\n[edges.left]\ntype = \"displacement\"\n").find("ux: missing"),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\n[edges.right]\ntype = \"traction\"\ntraction = [0, 1]\n")
                .find("nothing holds the structure"),
            std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\n[edges.left]\ntype = \"fixed\"\n").find("nothing loads"),
            std::string::npos);
  EXPECT_NE(
      refusal("[structure]\ncells = [2, 2]\n" + held + "[[support]]\nfix = \"y\"\n").find("[support 1] at: missing"),
      std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\n" + held + "[steps]\nfactors = [1, nan]\n")
                .find("[steps] factors: must be finite"),
            std::string::npos);
  EXPECT_NE(
      refusal("[structure]\ncells = [2, 2]\n" + held + "[solver]\nsteps = 3\n").find("[solver] steps = 3: unknown key"),
      std::string::npos);
  EXPECT_NE(refusal("[structure]\ncells = [2, 2]\n" + held + "[loads]\n").find("[top level] loads: unknown table"),
            std::string::npos);
}

}  // namespace
}  // namespace dualcell
