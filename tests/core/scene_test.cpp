// Scene parsing: every key validated, errors name the file, the key, the value and the range.
#include "core/scene.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>

#include "core/error.hpp"
#include "core/structure_scene.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::scene_text;

std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "scene.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, DefaultsAndValues) {
  const Scene s = parse_scene(scene_text(3, 2, 4, 0.25, "[load]\nboundary = \"periodic\"\n"), "x.toml");
  EXPECT_EQ(s.geometry.cells[0], 3);
  EXPECT_EQ(s.geometry.cells[1], 2);
  EXPECT_EQ(s.geometry.degree, 4);
  EXPECT_DOUBLE_EQ(s.geometry.fibre_radius, 0.25);
  EXPECT_EQ(s.load.boundary, Boundary::periodic);
  EXPECT_EQ(s.solver.preconditioner, Preconditioner::none);
  EXPECT_EQ(s.solver.rho_growth, 10.0);
  EXPECT_EQ(s.solver.rho_patience, 5);
  EXPECT_EQ(s.solver.subdomain_dofs, 0);  // an RVE's matrix whole
  const Scene plain = parse_scene(scene_text(1, 1, 1, 0.3, "[solver]\nrho_growth = 1\nrho_patience = 2\n"), "x.toml");
  EXPECT_EQ(plain.solver.rho_growth, 1.0);
  EXPECT_EQ(plain.solver.rho_patience, 2);
  EXPECT_EQ(parse_scene(scene_text(1, 1, 1, 0.3, "[solver]\npreconditioner = \"dirichlet\"\n"), "x.toml")
                .solver.preconditioner,
            Preconditioner::dirichlet);
  EXPECT_EQ(
      parse_scene(scene_text(1, 1, 1, 0.3, "[solver]\npreconditioner = \"lumped\"\n"), "x.toml").solver.preconditioner,
      Preconditioner::lumped);
  EXPECT_DOUBLE_EQ(s.fibre.E, 100.0);
  EXPECT_DOUBLE_EQ(s.matrix.nu, 0.35);
  EXPECT_FALSE(s.interface.has_adhesion());
  EXPECT_EQ(s.text.substr(0, 10), "[geometry]");
}

TEST(Scene, ErrorsNameFileKeyValueAndRange) {
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {scene_text(1, 1, 1, -0.1), "[geometry] fibre_radius = -0.100000: out of range: fibre_radius > 0"},
      {scene_text(1, 1, 1, 0.5), "fibre touches or crosses its cell's edge"},
      {scene_text(1, 1, 0, 0.3), "[geometry] degree = 0: out of range: an integer in [1, 256]"},
      {scene_text(0, 1, 1, 0.3), "[geometry] cells = [0, 1]: out of range"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 1\nnu = 0.5\n[matrix]\nE = 1\nnu = 0.3\n",
       "[fibre] nu = 0.5: out of range: -1 < nu < 0.5"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 1\nnu = -1\n[matrix]\nE = 1\nnu = 0.3\n",
       "[fibre] nu = -1: out of range"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 0\nnu = 0.2\n[matrix]\nE = 1\nnu = 0.3\n",
       "[fibre] E = 0: out of range: E > 0"},
      // A transversely isotropic phase: all three axial constants, its compliance positive definite.
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 15\nnu = 0.07\nE_L = 230\n[matrix]\nE = 1\nnu = 0.3\n",
       "[fibre] nu_LT: missing; required, a transversely isotropic phase gives E_L, nu_LT and G_LT"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 15\nnu = 0.07\nE_L = 230\nnu_LT = 0.2\nG_LT = 0\n"
       "[matrix]\nE = 1\nnu = 0.3\n",
       "[fibre] G_LT = 0: out of range: G_LT > 0"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 15\nnu = 0.5\nE_L = 10\nnu_LT = 0.9\nG_LT = 5\n"
       "[matrix]\nE = 1\nnu = 0.3\n",
       "[fibre] nu_LT = 0.9: out of range: 1 - nu - 2 nu_LT^2 E/E_L > 0"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 15\nnu = 1\nE_L = 230\nnu_LT = 0.2\nG_LT = 15\n"
       "[matrix]\nE = 1\nnu = 0.3\n",
       "[fibre] nu = 1: out of range: -1 < nu < 1"},
      // Expansion: per kelvin (a value in ppm is refused), alpha_L only beside alpha on a transversely
      // isotropic phase, and a temperature change only with both phases' alpha.
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 70\nnu = 0.2\nalpha = 5\n[matrix]\nE = 3\nnu = 0.35\n",
       "[fibre] alpha = 5: out of range: |alpha| <= 1e-3 per kelvin (a strain per kelvin, not ppm)"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 70\nnu = 0.2\nalpha = 5e-6\nalpha_L = 1e-6\n[matrix]\nE = "
       "3\nnu = 0.35\n",
       "[fibre] alpha_L: only for a transversely isotropic phase"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 15\nnu = 0.07\nE_L = 230\nnu_LT = 0.2\nG_LT = 15\nalpha_L = "
       "-5e-7\n[matrix]\nE = 3\nnu = 0.35\n",
       "[fibre] alpha_L: needs alpha, the expansion across the fibres, beside it"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 70\nnu = 0.2\nalpha = 5e-6\n[matrix]\nE = 3\nnu = 0.35\n[load]\n"
       "delta_T = -100\n",
       "[load] delta_T = -100: a temperature change needs both phases' expansion: give [matrix] alpha"},
      {"[geometry]\nfibre_radius = 0.3\n[fibre]\nE = 70\nnu = 0.2\nalpha = 5e-6\n[matrix]\nE = 3\nnu = 0.35\nalpha = "
       "6e-5\n[load]\ndelta_T = -2000\n",
       "[load] delta_T = -2000: out of range: |delta_T| <= 1000"},
      {scene_text(1, 1, 1, 0.3, "[interface]\nnormal_strenght = 1\n"), "[interface] normal_strenght = 1: unknown key"},
      {scene_text(1, 1, 1, 0.3, "[bogus]\n"), "bogus: unknown table or key"},
      {scene_text(1, 1, 1, 0.3, "[load]\nboundary = \"free\"\n"),
       "[load] boundary = \"free\": must be one of \"symmetry\", \"traction\", \"periodic\""},
      {scene_text(1, 1, 1, 0.3, "[solver]\npreconditioner = \"jacobi\"\n"),
       "[solver] preconditioner = \"jacobi\": must be one of \"none\", \"lumped\", \"dirichlet\""},
      {scene_text(1, 1, 1, 0.3, "[solver]\nrho_growth = 0.5\n"),
       "[solver] rho_growth = 0.5: out of range: 1 <= rho_growth <= 1e3"},
      {scene_text(1, 1, 1, 0.3, "[solver]\nrho_patience = 0\n"), "[solver] rho_patience = 0: out of range"},
      {scene_text(1, 1, 1, 0.3, "[solver]\nsubdomain_dofs = 50\n"),
       "[solver] subdomain_dofs = 50: out of range: 0 (an RVE's matrix whole) or an integer in [100, 10000000]"},
      {scene_text(1, 1, 1, 0.3, "[load\n"), "TOML syntax error"},
      {"[geometry]\nfibre_radius = \"big\"\n", "[geometry] fibre_radius = \"big\": must be a number"},
      {"[geometry]\nfibre_radius = 0.3\n", "missing table [fibre]"},
      {scene_text(1, 1, 1, 0.3, "[solver]\ntolerance = 2\n"), "[solver] tolerance = 2: out of range"},
      {scene_text(1, 1, 1, 0.3, "[sweep]\nmagnitudes = [1, 0]\n"), "[sweep] magnitudes"},
      {scene_text(1, 1, 1, 0.3, "[load]\nboundary = \"traction\"\nbody_force = [0, -1]\n"),
       "[load] body_force = [0, -1]: a body force needs boundary = \"symmetry\""},
      {scene_text(1, 1, 1, 0.3, "[interface]\nnormal_strength = 1\n[load]\nbody_force = [0, -1]\n"),
       "a body force cannot be combined with adhesion"},
      // Edge tables belong to boundary = "edges", which needs something holding and loading it.
      {scene_text(1, 1, 1, 0.3, "[edges.left]\ntype = \"fixed\"\n"),
       "edges: only with [load] boundary = \"edges\" (the boundary here is \"symmetry\")"},
      {scene_text(1, 1, 1, 0.3,
                  "[load]\nboundary = \"edges\"\n[edges.right]\ntype = \"traction\"\ntraction = [1, 0]\n"),
       "nothing holds the block"},
      {scene_text(1, 1, 1, 0.3, "[load]\nboundary = \"edges\"\n[edges.left]\ntype = \"fixed\"\n"),
       "nothing loads the block"},
      {scene_text(1, 1, 1, 0.3, "[load]\nboundary = \"edges\"\n[edges.left]\ntype = \"glued\"\n"),
       "[edges.left] type = \"glued\": must be one of"},
      // An array beyond its size names its limit (once "at least 0 numbers" for 200 values).
      {scene_text(
           1, 1, 1, 0.3,
           "[load]\nboundary = \"periodic\"\nmacro = \"full\"\n[sweep]\neps33 = [" +
               [] {
                 std::string v = "0.001";
                 for (int i = 1; i < 200; ++i) v += ", 0.001";
                 return v;
               }() +
               "]\n"),
       "must be an array of at most 100 numbers"},
      // A magnitude that strains the softer phase (E = 1) by 1e200: no finite answer.
      {scene_text(1, 1, 1, 0.3, "[sweep]\nmagnitudes = [1, 1e200]\n"),
       "[sweep] magnitudes = [1, 1e200]: out of range: it strains the softer phase (E = 1) beyond 1e+100"},
  };
  for (const auto& c : cases) {
    const std::string message = error_of(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "got: " << message << "\nfor:\n" << c.text;
    EXPECT_EQ(message.rfind("scene.toml", 0), 0u) << message;  // starts with the file name
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  }
}

// validate() is the one range check: a scene built in code gets the message a file gets, with
// "scene" (or its file name) in place of file:line:column and the value as stored.
TEST(Scene, ScenesBuiltInCodeAreValidatedWithTheSameMessages) {
  struct Case {
    std::function<void(Scene&)> edit;
    std::string toml_extra, expected;
  };
  const std::vector<Case> cases = {
      {[](Scene& s) { s.geometry.degree = 0; }, "", "[geometry] degree = 0: out of range: an integer in [1, 256]"},
      {[](Scene& s) { s.matrix.nu = 0.5; }, "", "[matrix] nu = 0.5: out of range: -1 < nu < 0.5"},
      {[](Scene& s) { s.interface.normal_strength = -1; }, "[interface]\nnormal_strength = -1\n",
       "[interface] normal_strength = -1: out of range: normal_strength >= 0"},
      {[](Scene& s) {
         s.sweep.magnitudes = {1, 0};
       },
       "[sweep]\nmagnitudes = [1, 0]\n",
       "[sweep] magnitudes = [1, 0]: out of range: must be an array of at least 1 numbers, each non-zero"},
      {[](Scene& s) { s.solver.rho_growth = 0.5; }, "[solver]\nrho_growth = 0.5\n",
       "[solver] rho_growth = 0.5: out of range: 1 <= rho_growth <= 1e3"},
      {[](Scene& s) { s.geometry.fibre_radius = 0.5; }, "", "fibre touches or crosses its cell's edge"},
  };
  for (const auto& c : cases) {
    Scene scene = parse_scene(scene_text(1, 1, 1, 0.3), "scene.toml");
    EXPECT_NO_THROW(validate(scene));
    scene.written.clear();  // as if built in code
    scene.file.clear();
    c.edit(scene);
    std::string message;
    try {
      validate(scene);
    } catch (const InputError& e) {
      message = e.what();
    }
    EXPECT_EQ(message.rfind("scene: ", 0), 0u) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
    if (!c.toml_extra.empty()) {  // the same words from a file, after its file:line:column
      const std::string from_file = error_of(scene_text(1, 1, 1, 0.3, c.toml_extra));
      EXPECT_EQ(from_file.substr(from_file.find(": [") + 2), message.substr(message.find(": [") + 2)) << from_file;
    }
  }
}

TEST(Scene, LineNumbersPointAtTheKey) {
  const std::string message = error_of(scene_text(1, 1, 1, 0.3, "[interface]\nnormal_strength = -2\n"));
  // scene_text has 13 lines, then "[interface]" on line 14 and the key on line 15.
  EXPECT_NE(message.find("scene.toml:15:"), std::string::npos) << message;
}

TEST(Scene, MaterialFileResolvesAgainstSceneFolder) {
  testing::ScratchDir dir;
  std::filesystem::create_directories(dir / "materials");
  dir.write("materials/m.toml", "source = \"test\"\n[fibre]\nE = 7\nnu = 0.1\n[matrix]\nE = 2\nnu = 0.3\n");
  const auto scene = dir.write("s.toml", "material = \"materials/m.toml\"\n[geometry]\nfibre_radius = 0.3\n");
  const Scene s = load_scene(scene);
  EXPECT_DOUBLE_EQ(s.fibre.E, 7);
  EXPECT_DOUBLE_EQ(s.matrix.E, 2);
  EXPECT_NE(s.material_text.find("source"), std::string::npos);

  const auto both = dir.write("b.toml",
                              "material = \"materials/m.toml\"\n[geometry]\nfibre_radius = 0.3\n"
                              "[fibre]\nE = 1\nnu = 0.1\n");
  EXPECT_THROW(load_scene(both), InputError);
  const auto missing = dir.write("c.toml", "material = \"nope.toml\"\n[geometry]\nfibre_radius = 0.3\n");
  try {
    load_scene(missing);
    FAIL() << "missing material file accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("material file not found"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_scene(dir / "absent.toml"), InputError);
}

// Cell scenes and structure scenes (those with a [structure] table) alike.
TEST(Scene, CommittedScenesAndMaterialsParse) {
  int structures = 0;
  for (const auto& entry : std::filesystem::directory_iterator(testing::source_dir() + "/pipelines/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    std::ifstream in(entry.path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find("\n[structure]") != std::string::npos) {
      ++structures;
      EXPECT_NO_THROW(load_structure_scene(entry.path())) << entry.path();
    } else {
      EXPECT_NO_THROW(load_scene(entry.path())) << entry.path();
    }
  }
  EXPECT_GE(structures, 1);
}

}  // namespace
}  // namespace dualcell
