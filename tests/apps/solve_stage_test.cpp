// dualcell-solve as a user runs it: output layout, XDMF of the deformed shape, refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "core/exit_codes.hpp"
#include "io/hdf5.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;
using testing::run_command;

struct Prepared {
  testing::ScratchDir dir;
  std::filesystem::path scene, mesh;
};

void prepare(Prepared& p, const std::string& extra) {
  p.scene = p.dir.write("s.toml", testing::scene_text(2, 1, 2, 0.3, extra));
  p.mesh = p.dir / "mesh.h5";
  const auto r =
      run_command(bin("dualcell-mesh") + " --quiet --config " + p.scene.string() + " --out " + p.mesh.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
}

TEST(SolveStage, WritesTheDocumentedLayout) {
  Prepared p;
  prepare(p, "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n[load]\nboundary = \"traction\"\n");
  const auto out = p.dir / "solution.h5";
  const auto r = run_command(bin("dualcell-solve") + " --config " + p.scene.string() + " --mesh " + p.mesh.string() +
                             " --stress 0.2,0,0.05 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* text : {"status converged", "macro strain", "KKT", "seconds: assembly", "debond rounds"})
    EXPECT_NE(r.output.find(text), std::string::npos) << text << "\n" << r.output;
  io::File f = io::File::open_read(out);
  for (const char* name : {"/solution/u", "/solution/element_stress", "/interface/lambda", "/interface/bonded",
                           "/interface/opening", "/macro/stress", "/macro/strain", "/macro/average_stress"})
    EXPECT_TRUE(f.exists(name)) << name;
  EXPECT_EQ(f.read_string_attribute("/solver", "status"), "converged");
  EXPECT_GT(f.read_int_attribute("/solver", "operator_applications")[0], 0);
  for (const char* attr : {"relative_projected_gradient", "relative_equality_residual", "bound_violation",
                           "complementarity", "max_penetration", "max_glue_jump", "relative_equilibrium"})
    EXPECT_TRUE(f.has_attribute("/kkt", attr)) << attr;
  const auto stress = f.read_doubles("/macro/stress", {3});
  EXPECT_EQ(stress, (std::vector<double>{0.2, 0, 0.05}));
  // The bond state written here is the input of the next load: bonds broken at 0.2 stay
  // broken at the lower 0.005, where the intact interface holds.
  const auto bonded = f.read_ints("/interface/bonded", {io::any_extent});
  const long broken = std::count(bonded.begin(), bonded.end(), 0);
  EXPECT_GT(broken, 0);
  const auto r2 =
      run_command(bin("dualcell-solve") + " --quiet --config " + p.scene.string() + " --mesh " + p.mesh.string() +
                  " --stress 0.005,0,0 --bonds " + out.string() + " --out " + (p.dir / "next.h5").string());
  EXPECT_EQ(r2.exit_code, 0) << r2.output;
  const auto after = io::File::open_read(p.dir / "next.h5").read_ints("/interface/bonded", {io::any_extent});
  for (std::size_t i = 0; i < bonded.size(); ++i)
    if (!bonded[i]) {
      EXPECT_EQ(after[i], 0) << "bond " << i << " healed";
    }
  const auto r_fresh = run_command(bin("dualcell-solve") + " --quiet --config " + p.scene.string() + " --mesh " +
                                   p.mesh.string() + " --stress 0.005,0,0 --out " + (p.dir / "fresh.h5").string());
  EXPECT_EQ(r_fresh.exit_code, 0) << r_fresh.output;
  const auto fresh = io::File::open_read(p.dir / "fresh.h5").read_ints("/interface/bonded", {io::any_extent});
  EXPECT_EQ(std::count(fresh.begin(), fresh.end(), 0), 0) << "0.005 breaks nothing from the intact state";
  // ParaView's reader path: meshio opens the XDMF with the deformed geometry and its fields.
  const auto py = p.dir.write("read.py",
                              "import meshio, sys\nm = meshio.read(sys.argv[1])\n"
                              "print(len(m.points), sorted(m.point_data), sorted(m.cell_data))\n");
  const auto r3 = run_command("/usr/bin/python3 " + py.string() + " " + (p.dir / "solution.xdmf").string());
  ASSERT_EQ(r3.exit_code, 0) << r3.output;
  EXPECT_NE(r3.output.find("['displacement'] ['stress', 'stress_average', 'subdomain']"), std::string::npos)
      << r3.output;
}

TEST(SolveStage, RefusesMismatchedMeshShearOnSymmetryAndBadStress) {
  Prepared p;
  prepare(p, "");
  const auto out = p.dir / "solution.h5";
  const std::string base = bin("dualcell-solve") + " --config ";
  struct Case {
    std::string scene_extra, stress, expected;
  };
  // A scene with another degree than the mesh.
  const auto other = p.dir.write("other.toml", testing::scene_text(2, 1, 3, 0.3));
  auto r = run_command(base + other.string() + " --mesh " + p.mesh.string() + " --stress 1,0,0 --out " + out.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("made from a different scene"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[geometry] degree: mesh 2, scene 3"), std::string::npos) << r.output;
  r = run_command(base + p.scene.string() + " --mesh " + p.mesh.string() + " --stress 1,0,0.5 --out " + out.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("symmetry boundary carries only sxx and syy"), std::string::npos) << r.output;
  r = run_command(base + p.scene.string() + " --mesh " + p.mesh.string() + " --stress 1,x,0 --out " + out.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("'x' is not a finite number"), std::string::npos) << r.output;
  r = run_command(base + p.scene.string() + " --mesh " + p.scene.string() + " --stress 1,0,0 --out " + out.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("not an HDF5 file"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(p.dir / "solution.xdmf"));
}

}  // namespace
}  // namespace dualcell

namespace dualcell {
namespace {

// --eps33 (generalised plane strain, docs/method.md §3a): the summary's longitudinal line and
// the datasets that only such a file has, with σzz between the phases' (a stretch along the
// fibres, free across); a plane-strain file has none of them, and an ε33 out of range is refused.
TEST(SolveStage, ALongitudinalStrainWritesTheLongitudinalStress) {
  Prepared p;
  prepare(p, "[load]\nboundary = \"periodic\"\n");
  const std::string cfg = " --config " + p.scene.string() + " --mesh " + p.mesh.string();
  const auto out = p.dir / "solution.h5";
  const auto r = run_command(bin("dualcell-solve") + cfg + " --stress 0,0,0 --eps33 0.01 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("longitudinal  e33 1.000000e-02 (given), <szz>"), std::string::npos) << r.output;
  const io::File f = io::File::open_read(out);
  EXPECT_EQ(f.read_doubles("/macro/eps33", {1})[0], 0.01);
  const double zz = f.read_doubles("/macro/average_stress_zz", {1})[0];
  const auto triangles = f.read_ints("/mesh/triangle_subdomain", {io::any_extent});
  const auto element_zz = f.read_doubles("/solution/element_stress_zz_average", {triangles.size()});
  double lowest = element_zz[0], highest = element_zz[0];
  for (double v : element_zz) lowest = std::min(lowest, v), highest = std::max(highest, v);
  // Stretched along the fibres and free across: every element pulls, the stiff fibres most, and
  // the average lies between (E_m = 1 < ⟨σzz⟩/ε33 < E_f = 100).
  EXPECT_GT(lowest, 0);
  EXPECT_GT(zz, lowest);
  EXPECT_LT(zz, highest);
  EXPECT_GT(zz / 0.01, 1.0);
  EXPECT_LT(zz / 0.01, 100.0);
  const auto plane = p.dir / "plane.h5";
  const auto r2 = run_command(bin("dualcell-solve") + " --quiet" + cfg + " --stress 0.01,0,0 --out " + plane.string());
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  const io::File g = io::File::open_read(plane);
  for (const char* name : {"/macro/eps33", "/macro/average_stress_zz", "/solution/element_stress_zz_average"})
    EXPECT_FALSE(g.exists(name)) << name;
  const auto bad =
      run_command(bin("dualcell-solve") + cfg + " --stress 0,0,0 --eps33 2 --out " + (p.dir / "bad.h5").string());
  EXPECT_NE(bad.exit_code, 0) << bad.output;
  EXPECT_NE(bad.output.find("--eps33"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(p.dir / "bad.h5"));
}

// A scene with a temperature change (docs/theory/model.md §1a): dualcell-solve cools it first at
// zero macro stress and says how many bonds that broke (here the matrix, expanding ten times
// more than the fibre, shrinks onto it: a square cell's rim carries shear, which breaks the
// weakest tangential bonds), then loads it from there; the file holds ΔT and σzz. The sweep
// starts every path from the cool-down and records ΔT; the fit, which does not carry it yet,
// refuses that sweep in one line and writes nothing.
TEST(SolveStage, ATemperatureChangeIsSolvedFirstThenTheLoad) {
  Prepared p;
  const std::string thermal =
      "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.0002\n[load]\nboundary = "
      "\"periodic\"\ndelta_T = -100\n";
  std::string text = testing::scene_text(2, 1, 2, 0.3, thermal);
  text.replace(text.find("nu = 0.2\n"), 9, "nu = 0.2\nalpha = 5e-6\n");
  text.replace(text.find("nu = 0.35\n"), 10, "nu = 0.35\nalpha = 6e-5\n");
  p.scene = p.dir.write("s.toml", text);
  p.mesh = p.dir / "mesh.h5";
  ASSERT_EQ(run_command(bin("dualcell-mesh") + " --quiet --config " + p.scene.string() + " --out " + p.mesh.string())
                .exit_code,
            0);
  const std::string cfg = " --config " + p.scene.string() + " --mesh " + p.mesh.string();
  const auto out = p.dir / "solution.h5";
  const auto r = run_command(bin("dualcell-solve") + cfg + " --stress 0.001,0,0 --onset --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The cool-down broke bonds already: the onset along any stress from it is 0.
  EXPECT_NE(r.output.find("debond onset  s* = 0 along this stress (first break of the intact interface at s* x "
                          "stress, from the cool-down)"),
            std::string::npos)
      << r.output;
  const auto with_eps33 = run_command(bin("dualcell-solve") + cfg + " --stress 0.001,0,0 --eps33 1e-3 --onset --out " +
                                      (p.dir / "e.h5").string());
  EXPECT_EQ(with_eps33.exit_code, exit_input_error) << with_eps33.output;
  EXPECT_NE(with_eps33.output.find("--onset: not with --eps33"), std::string::npos) << with_eps33.output;
  const auto at = r.output.find("cool-down     delta_T -100 K at zero macro stress, solved first: ");
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_GT(std::stol(r.output.substr(r.output.find(':', at + 20) + 2)), 0) << r.output;
  const io::File f = io::File::open_read(out);
  EXPECT_EQ(f.read_doubles("/macro/delta_T", {1})[0], -100);
  EXPECT_FALSE(f.exists("/macro/eps33"));
  // Plane strain along z: the matrix, held at ε33 = 0 while it would shrink most, pulls along z.
  EXPECT_GT(f.read_doubles("/macro/average_stress_zz", {1})[0], 0);
  const auto sweep = run_command(bin("dualcell-sweep") + cfg + " --quiet --out " + (p.dir / "sweep.h5").string());
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  EXPECT_EQ(io::File::open_read(p.dir / "sweep.h5").read_double_attribute_value("/", "delta_T"), -100);
  const auto fit = run_command(bin("dualcell-fit") + " --sweep " + (p.dir / "sweep.h5").string() + " --out " +
                               (p.dir / "law.h5").string());
  EXPECT_EQ(fit.exit_code, exit_input_error) << fit.output;
  EXPECT_NE(fit.output.find("delta_T = -100: the fit does not carry a temperature change yet"), std::string::npos)
      << fit.output;
  EXPECT_FALSE(std::filesystem::exists(p.dir / "law.h5"));
  // Adhesion in shear only keeps the normal rows contact rows: no affine onset, refused before any path.
  std::string shear_only = text;
  shear_only.replace(shear_only.find("normal_strength = 0.05"), 22, "normal_strength = 0");
  const auto shear_scene = p.dir.write("shear.toml", shear_only);
  const auto refused = run_command(bin("dualcell-sweep") + " --config " + shear_scene.string() + " --mesh " +
                                   p.mesh.string() + " --out " + (p.dir / "shear.h5").string());
  EXPECT_EQ(refused.exit_code, exit_input_error) << refused.output;
  EXPECT_NE(refused.output.find("with adhesion in shear only ([interface] normal_strength = 0)"), std::string::npos)
      << refused.output;
  EXPECT_FALSE(std::filesystem::exists(p.dir / "shear.h5"));
}

// A load is an ordinary load however small, and one whose answer cannot be finite in doubles is
// refused before the work, with one line and exit 1: a 1 × 1 p1 cell with adhesion.
TEST(SolveStage, ALoadBeyondDoublesIsRefusedAndATinyOneIsAnOrdinaryLoad) {
  Prepared p;
  p.scene =
      p.dir.write("s.toml", testing::scene_text(1, 1, 1, 0.3,
                                                "[interface]\nnormal_strength = 0.01\ntangential_strength = 0.01\n"
                                                "[load]\nboundary = \"periodic\"\n",
                                                "p1"));
  p.mesh = p.dir / "mesh.h5";
  ASSERT_EQ(run_command(bin("dualcell-mesh") + " --quiet --config " + p.scene.string() + " --out " + p.mesh.string())
                .exit_code,
            0);
  const std::string cfg =
      bin("dualcell-solve") + " --quiet --config " + p.scene.string() + " --mesh " + p.mesh.string();
  const auto out = p.dir / "solution.h5";
  // 1e308 strains the matrix (E = 1) by 1e308: refused, nothing written (it once ran and wrote
  // strains of inf and NaN).
  for (const std::string& load : {std::string(" --stress 1e308,0,0"), std::string(" --stress 0,-1e101,0")}) {
    const auto huge = run_command(cfg + load + " --out " + out.string());
    EXPECT_EQ(huge.exit_code, exit_input_error) << huge.output;
    EXPECT_EQ(testing::occurrences(huge.output, "\n"), 1u) << huge.output;
    EXPECT_NE(huge.output.find("no finite answer in doubles"), std::string::npos) << huge.output;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  const auto not_a_number = run_command(cfg + " --stress 0,0,0 --eps33 nan --out " + out.string());
  EXPECT_EQ(not_a_number.exit_code, exit_input_error) << not_a_number.output;
  EXPECT_NE(not_a_number.output.find("--eps33: 'nan' is not a finite number"), std::string::npos)
      << not_a_number.output;
  EXPECT_EQ(testing::occurrences(not_a_number.output, "\n"), 1u) << not_a_number.output;
  // ε33 = 1e-300 at zero stress (it once failed the primal check, exit 4) is the answer at 1e-3
  // times 1e-297: the cell is linear while its bonds hold (1e-9: the two solves' tolerance).
  const auto tiny = run_command(cfg + " --stress 0,0,0 --eps33 1e-300 --out " + out.string());
  ASSERT_EQ(tiny.exit_code, exit_ok) << tiny.output;
  const auto ordinary = p.dir / "ordinary.h5";
  ASSERT_EQ(run_command(cfg + " --stress 0,0,0 --eps33 1e-3 --out " + ordinary.string()).exit_code, exit_ok);
  const auto small = io::File::open_read(out).read_doubles("/macro/strain", {3});
  const auto large = io::File::open_read(ordinary).read_doubles("/macro/strain", {3});
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(small[i] * 1e297, large[i], 1e-9 * std::abs(large[0])) << i;
  const double zz = io::File::open_read(ordinary).read_doubles("/macro/average_stress_zz", {1})[0];
  EXPECT_NEAR(io::File::open_read(out).read_doubles("/macro/average_stress_zz", {1})[0] * 1e297, zz,
              1e-9 * std::abs(zz));
}

// --longitudinal-shear (docs/method.md §3b): the longitudinal shear moduli with the bonds the
// load left. Bonded stiff fibres stiffen the matrix (μ_m = E/(2(1 + ν)) = 1/2.7); a load that
// breaks bonds lowers them; without adhesion (frictionless contact, no shear along z) the fibres
// are holes and the cell is softer than its matrix. Only a periodic cell has them.
TEST(SolveStage, TheLongitudinalShearModuliFollowTheBonds) {
  const double mu_m = 1 / 2.7;
  const auto moduli = [](const std::filesystem::path& file) {
    return io::File::open_read(file).read_doubles("/macro/longitudinal_shear_moduli", {2, 2});
  };
  Prepared bonded;
  prepare(bonded, "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n[load]\nboundary = \"periodic\"\n");
  const std::string cfg = " --config " + bonded.scene.string() + " --mesh " + bonded.mesh.string();
  const auto low = bonded.dir / "low.h5", high = bonded.dir / "high.h5";
  const auto r =
      run_command(bin("dualcell-solve") + cfg + " --stress 0.001,0,0 --longitudinal-shear --out " + low.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("longitudinal shear moduli (bonds as this load left them): Gxz"), std::string::npos)
      << r.output;
  ASSERT_EQ(run_command(bin("dualcell-solve") + " --quiet" + cfg + " --stress 0.3,0,0 --longitudinal-shear --out " +
                        high.string())
                .exit_code,
            0);
  const auto G_low = moduli(low), G_high = moduli(high);
  EXPECT_GT(G_low[0], mu_m);
  EXPECT_LT(G_high[0], G_low[0]) << "broken bonds carry no longitudinal shear";
  const io::File f = io::File::open_read(low);
  const auto nodes = f.read_doubles("/mesh/nodes", {io::any_extent, 2});
  for (const char* name : {"/solution/longitudinal_w_xz", "/solution/longitudinal_w_yz"})
    EXPECT_EQ(f.read_doubles(name, {io::any_extent}).size(), nodes.size() / 2) << name;
  // ParaView's reader path: the two w̃ fields are node fields of the XDMF.
  const auto py = low.parent_path() / "read.py";
  { std::ofstream(py) << "import meshio, sys\nm = meshio.read(sys.argv[1])\nprint(sorted(m.point_data))\n"; }
  const auto read = run_command("/usr/bin/python3 " + py.string() + " " + (bonded.dir / "low.xdmf").string());
  ASSERT_EQ(read.exit_code, 0) << read.output;
  EXPECT_NE(read.output.find("'longitudinal_w_xz', 'longitudinal_w_yz'"), std::string::npos) << read.output;

  Prepared contact;
  prepare(contact, "[load]\nboundary = \"periodic\"\n");
  const auto holes = contact.dir / "holes.h5";
  ASSERT_EQ(run_command(bin("dualcell-solve") + " --quiet --config " + contact.scene.string() + " --mesh " +
                        contact.mesh.string() + " --stress -0.01,0,0 --longitudinal-shear --out " + holes.string())
                .exit_code,
            0);
  EXPECT_LT(moduli(holes)[0], mu_m) << "without adhesion the fibres are holes along z";

  Prepared traction;
  prepare(traction, "[load]\nboundary = \"traction\"\n");
  const auto refused =
      run_command(bin("dualcell-solve") + " --config " + traction.scene.string() + " --mesh " + traction.mesh.string() +
                  " --stress 0.01,0,0 --longitudinal-shear --out " + (traction.dir / "x.h5").string());
  EXPECT_EQ(refused.exit_code, exit_input_error) << refused.output;
  EXPECT_NE(refused.output.find("needs \"periodic\""), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(traction.dir / "x.h5"));
}

// A block of resolved cells with edge conditions: load steps with the bond history, /steps in
// the documented layout, the first break factor; --stress, --eps33 and a sweep refused for it.
TEST(SolveStage, EdgesBoundarySolvesTheLoadStepsWithTheBondHistory) {
  Prepared p;
  prepare(p,
          "[interface]\nnormal_strength = 0.02\ntangential_strength = 0.02\n[load]\nboundary = \"edges\"\n"
          "[edges.left]\ntype = \"fixed\"\n[edges.right]\ntype = \"traction\"\ntraction = [0, -0.01]\n"
          "[steps]\nfactors = [0.5, 2.0, 0.5]\n[output]\nwatch = [2, 0]\n");
  const auto out = p.dir / "solution.h5";
  const std::string cfg = " --config " + p.scene.string() + " --mesh " + p.mesh.string();
  const auto r = run_command(bin("dualcell-solve") + cfg + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("first bond break at load factor"), std::string::npos) << r.output;
  const io::File f = io::File::open_read(out);
  const auto factor = f.read_doubles("/steps/factor", {3});
  EXPECT_EQ(factor, (std::vector<double>{0.5, 2.0, 0.5}));
  const auto broken = f.read_ints("/steps/broken", {3});
  const auto watch = f.read_doubles("/steps/watch_displacement", {3, 2});
  const double onset = f.read_double_attribute_value("/steps", "first_break_factor");
  EXPECT_GT(onset, 0);
  // Broken bonds never heal: the count does not fall when the load does, and the beam that has
  // lost bonds is softer at the same load (the first and the last step are both at 0.5).
  EXPECT_LE(broken[0], broken[1]);
  EXPECT_EQ(broken[1], broken[2]);
  EXPECT_LT(onset, 2.0);  // so the second step breaks bonds
  EXPECT_GT(broken[1], 0);
  EXPECT_LT(watch[5], 0);
  EXPECT_LE(watch[5], watch[1] * (1 + 1e-9));
  for (auto c : f.read_ints("/steps/converged", {3})) EXPECT_EQ(c, 1);
  // Refusals: --stress with an edges scene, and sweeping it.
  const auto stress =
      run_command(bin("dualcell-solve") + cfg + " --stress 0.01,0,0 --out " + (p.dir / "x.h5").string());
  EXPECT_EQ(stress.exit_code, exit_input_error) << stress.output;
  EXPECT_NE(stress.output.find("leave --stress out"), std::string::npos) << stress.output;
  const auto eps33 = run_command(bin("dualcell-solve") + cfg + " --eps33 0.01 --out " + (p.dir / "x.h5").string());
  EXPECT_EQ(eps33.exit_code, exit_input_error) << eps33.output;
  EXPECT_NE(eps33.output.find("leave --eps33 out"), std::string::npos) << eps33.output;
  const auto sweep = run_command(bin("dualcell-sweep") + cfg + " --out " + (p.dir / "sweep.h5").string());
  EXPECT_EQ(sweep.exit_code, exit_input_error) << sweep.output;
  EXPECT_FALSE(std::filesystem::exists(p.dir / "x.h5"));
  EXPECT_FALSE(std::filesystem::exists(p.dir / "sweep.h5"));
}

}  // namespace
}  // namespace dualcell
