// The whole ply's law through the stages (a scene with [load] macro = "full" on the periodic
// boundary, docs/method.md §16a): dualcell-law --full against an independent solve, the fit's
// checks of the shear and the strain along the fibres, its table of the ply's constants, the
// CalculiX cards from it; and sweep paths that hold a strain along the fibres.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

#include "core/exit_codes.hpp"
#include "core/text.hpp"
#include "io/hdf5.hpp"
#include "io/law_export.hpp"
#include "io/law_file.hpp"
#include "io/sweep_file.hpp"
#include "law/condensed.hpp"
#include "stages_run.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;
using testing::q;
using testing::read_csv;
using testing::run_command;
using testing::StagesRun;

// A ply whose phases have their expansion (docs/theory/model.md §1a): the sweep computes the
// bonded ply's α (two full solves, checked against Levin's relation in tests/feti/thermal_test.cpp),
// sweep.h5 keeps it, the fit carries it to law.h5 and its summary, and the export to the JSON and
// to the bonded ply's card as *EXPANSION, TYPE=ORTHO. Glass-like in epoxy-like: α1 lies between
// the phases' and near the fibre's (the fibres carry the axial stiffness), α2 = α3 near the
// matrix's (the square cell is symmetric: α23 round-off).
TEST(PlyStage, TheBondedPlysExpansionGoesFromTheSweepToTheCards) {
  testing::ScratchDir dir;
  std::string text = testing::scene_text(
      1, 1, 2, 0.35,
      "[interface]\nnormal_strength = 1e6\ntangential_strength = 1e6\n[load]\nboundary = \"periodic\"\nmacro = "
      "\"full\"\n[sweep]\ndirections_deg = [0, 45, 90]\nmagnitudes = [-0.02, 0.02]\n");
  text.replace(text.find("nu = 0.2\n"), 9, "nu = 0.2\nalpha = 5e-6\n");
  text.replace(text.find("nu = 0.35\n"), 10, "nu = 0.35\nalpha = 6e-5\n");
  const auto scene = dir.write("s.toml", text);
  const std::string cfg = " --quiet --config " + q(scene);
  ASSERT_EQ(run_command(bin("dualcell-mesh") + cfg + " --out " + q(dir / "mesh.h5")).exit_code, exit_ok);
  const auto sweep =
      run_command(bin("dualcell-sweep") + cfg + " --mesh " + q(dir / "mesh.h5") + " --out " + q(dir / "sweep.h5"));
  ASSERT_EQ(sweep.exit_code, exit_ok) << sweep.output;
  const auto fit = run_command(bin("dualcell-fit") + " --no-small-cell --sweep " + q(dir / "sweep.h5") + " --out " +
                               q(dir / "law.h5"));
  ASSERT_EQ(fit.exit_code, exit_ok) << fit.output;
  EXPECT_NE(fit.output.find("bonded ply's thermal expansion per K (axis 1 the fibres; /law/expansion): alpha1 "),
            std::string::npos)
      << fit.output;
  const law::PlyExpansion swept = io::read_sweep_header(dir / "sweep.h5").expansion;
  const law::PlyExpansion a = io::read_law(dir / "law.h5").ply.expansion;
  ASSERT_TRUE(swept.ok) << swept.note;
  EXPECT_EQ(a.alpha1, swept.alpha1);
  EXPECT_EQ(a.alpha2, swept.alpha2);
  EXPECT_EQ(a.alpha3, swept.alpha3);
  EXPECT_EQ(a.alpha23, swept.alpha23);
  EXPECT_GT(a.alpha1, 5e-6);
  EXPECT_LT(a.alpha1, 0.25 * 6e-5);
  EXPECT_GT(a.alpha2, 0.5 * 6e-5);
  // The square cell's symmetry, to the sweep's dual tolerance (1e-8, the scene's default) with
  // cond(PFP)'s margin: measured 1.7e-9 and 7e-9 of α2.
  EXPECT_NEAR(a.alpha3, a.alpha2, 1e-7 * a.alpha2);
  EXPECT_LE(std::abs(a.alpha23), 1e-7 * a.alpha2);
  const law::Law fitted = io::read_law(dir / "law.h5");
  EXPECT_NE(io::law_json(fitted).find("\"expansion\": {"), std::string::npos);
  const std::string cards = io::law_calculix(fitted, "GLASS", "law.h5");
  EXPECT_NE(cards.find("*EXPANSION, TYPE=ORTHO\n" + formatted("%.12e", a.alpha1) + ", " + formatted("%.12e", a.alpha2)),
            std::string::npos)
      << cards;
  // Once per bonded card (tension and compression), on no other.
  std::size_t count = 0;
  for (std::size_t at = cards.find("*EXPANSION"); at != std::string::npos; at = cards.find("*EXPANSION", at + 1))
    ++count;
  EXPECT_EQ(count, 2u);
}

// The whole ply (dualcell-law --full): rows of six strains, the six stresses and the 6 × 6
// tangent. Bonded and sheared along the fibres a little, C55, C56, C66 are the cell's longitudinal
// shear moduli as dualcell-solve --longitudinal-shear computes them in one body (an independent
// solve; both exact for the mesh: 1e-9, the condensation's round-off with margin), and ⟨τ⟩ = C Γ;
// the in-plane and ε33 block is --eps33's, and nothing couples it to the shears. Sheared along
// the fibres past the bonds' strength, pairs break, and the modulus falls, irreversibly, towards
// the matrix with holes (the open cell's, a debonded frictionless fibre carries no shear).
TEST(PlyStage, DualcellLawEvaluatesTheWholePly) {
  const std::string scene = testing::scene_text(
      1, 1, 2, 0.3,
      "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n[load]\nboundary = \"periodic\"\nmacro = "
      "\"full\"\n[sweep]\ndirections_deg = [0, 45, 90]\nmagnitudes = [-0.01, 0.01]\n[solver]\ntolerance = 1e-10\n");
  StagesRun run(scene);
  const auto solved =
      run_command(bin("dualcell-solve") + " --quiet --config " + q(run.dir / "s.toml") + " --mesh " +
                  q(run.dir / "mesh.h5") + " --stress 0,0,0 --longitudinal-shear --out " + q(run.dir / "solution.h5"));
  ASSERT_EQ(solved.exit_code, exit_ok) << solved.output;
  const std::vector<double> G =
      io::File::open_read(run.dir / "solution.h5").read_doubles("/macro/longitudinal_shear_moduli", {2, 2});
  const double g = 1e-4;
  const auto points = run.dir.write("p.csv",
                                    "path,exx,eyy,gxy,e33,gxz,gyz\n"
                                    "1,1e-4,-5e-5,2e-5,1e-4,1e-4,0\n"
                                    "1,1e-4,-5e-5,2e-5,1e-4,0,1e-4\n"
                                    "2,0,0,0,0,1,0\n"
                                    "2,0,0,0,0,1e-4,0\n");
  const auto a = run_command(bin("dualcell-law") + " --quiet --law " + q(run.law) + " --strain " + q(points) +
                             " --full --out " + q(run.dir / "full.csv"));
  ASSERT_EQ(a.exit_code, exit_ok) << a.output;
  std::string header;
  const auto rows = read_csv(run.dir / "full.csv", &header);
  EXPECT_EQ(header.rfind("path,sxx,syy,sxy,szz,sxz,syz,C11,C12,", 0), 0u) << header;
  EXPECT_NE(header.find(",C65,C66,broken_pairs"), std::string::npos) << header;
  ASSERT_EQ(rows.size(), 4u);
  const auto C = [&](std::size_t row, int i, int j) { return rows[row][7 + 6 * (i - 1) + (j - 1)]; };
  for (std::size_t r = 0; r < 2; ++r) {
    EXPECT_NEAR(C(r, 5, 5), G[0], 1e-9 * G[0]);
    EXPECT_NEAR(C(r, 5, 6), G[1], 1e-9 * G[0]);
    EXPECT_NEAR(C(r, 6, 6), G[3], 1e-9 * G[0]);
    for (int i = 1; i <= 4; ++i)
      for (int j = 5; j <= 6; ++j) {
        EXPECT_EQ(C(r, i, j), 0) << i << j;
        EXPECT_EQ(C(r, j, i), 0) << j << i;
      }
    EXPECT_EQ(rows[r].back(), 0) << "bonded";
  }
  EXPECT_NEAR(rows[0][5], G[0] * g, 1e-9 * G[0] * g);
  EXPECT_NEAR(rows[1][6], G[3] * g, 1e-9 * G[0] * g);
  // The in-plane and ε33 block against --eps33 at the same strains.
  const auto four = run.dir.write("four.csv", "exx,eyy,gxy,e33\n1e-4,-5e-5,2e-5,1e-4\n");
  ASSERT_EQ(run_command(bin("dualcell-law") + " --quiet --law " + q(run.law) + " --strain " + q(four) +
                        " --eps33 --out " + q(run.dir / "four_out.csv"))
                .exit_code,
            exit_ok);
  const auto in_plane = read_csv(run.dir / "four_out.csv");
  for (int k = 0; k < 4; ++k) EXPECT_EQ(rows[0][1 + k], in_plane[0][k]) << k;
  for (int i = 1; i <= 4; ++i)
    for (int j = 1; j <= 4; ++j) EXPECT_EQ(C(0, i, j), in_plane[0][4 + 4 * (i - 1) + (j - 1)]) << i << j;
  // Path 2: sheared far past the strength, then back to a small shear: broken, softer, above the
  // matrix with holes' modulus (which a cell without bonds has: D0z of the same cell).
  EXPECT_GT(rows[2].back(), 0);
  EXPECT_EQ(rows[3].back(), rows[2].back());
  EXPECT_LT(C(3, 5, 5), G[0]);
  const law::Law fitted = io::read_law(run.law);
  const law::CondensedCell& cell = *fitted.cell;
  EXPECT_GE(C(3, 5, 5), cell.D0z(0, 0) * (1 - 1e-12));
  // The fit's table of the ply's constants (/law/ply): bonded and after the fuse, both signs;
  // the bonded G12, G13 the solve's, through law.h5; printed in the summary and in the JSON.
  ASSERT_EQ(fitted.ply.rows.size(), 4u) << fitted.ply.note;
  const double det = G[0] * G[3] - G[1] * G[2];
  EXPECT_NEAR(fitted.ply.rows[0].G12, det / G[3], 1e-9 * G[0]);
  EXPECT_NEAR(fitted.ply.rows[1].G13, det / G[0], 1e-9 * G[0]);
  EXPECT_EQ(fitted.ply.rows[2].state, law::PlyState::after_fuse);
  EXPECT_GT(fitted.ply.rows[2].broken, 0);
  EXPECT_NE(run.fit_output.find("the ply's constants from the exact law"), std::string::npos) << run.fit_output;
  EXPECT_NE(io::law_json(fitted).find("\"ply\": {"), std::string::npos);
  // The fit replayed the sweep's one-body checks of the shear along the fibres (/shear_check:
  // four paths through the cascade along z) to round-off, the same pairs broken; a sweep whose
  // checks say otherwise (a τ moved by 1e-4) is refused, the law not written.
  // The CalculiX export carries the ply's cards from /law/ply (fibres along axis 1), one per state
  // and sign, with the law's constants.
  const auto cards = run_command(bin("dualcell-export") + " --quiet --law " + q(run.law) +
                                 " --format calculix --name PLY --out " + q(run.dir / "cards.inp"));
  ASSERT_EQ(cards.exit_code, exit_ok) << cards.output;
  std::ifstream card_file(run.dir / "cards.inp");
  const std::string card_text((std::istreambuf_iterator<char>(card_file)), std::istreambuf_iterator<char>());
  for (const char* material : {"PLY_PLY_BONDED_TENSION", "PLY_PLY_BONDED_COMPRESSION", "PLY_PLY_AFTER_FUSE_TENSION"}) {
    const std::size_t at = card_text.find(std::string("*MATERIAL, NAME=") + material + "\n");
    ASSERT_NE(at, std::string::npos) << material;
    if (std::string(material) == "PLY_PLY_BONDED_TENSION") {
      const std::size_t numbers = card_text.find("CONSTANTS\n", at) + 10;
      EXPECT_NEAR(std::stod(card_text.substr(numbers)), fitted.ply.rows[0].E1, 1e-10 * fitted.ply.rows[0].E1);
    }
  }
  // The checks of the strain along the fibres reach past the fuse too (twice the onset along each
  // uniaxial path, ε33 of both signs, through the solver's debond loop): the law's cascade breaks
  // the same pairs.
  const std::vector<std::int64_t> broken_checks =
      io::File::open_read(run.sweep).read_ints("/longitudinal_check/broken", {io::any_extent});
  EXPECT_GT(*std::max_element(broken_checks.begin(), broken_checks.end()), 0);
  EXPECT_EQ(fitted.cell_longitudinal_replay.points, static_cast<int>(broken_checks.size()));
  EXPECT_EQ(fitted.cell_longitudinal_replay.break_mismatches, 0);
  EXPECT_EQ(fitted.cell_shear_replay.points, 16);
  EXPECT_EQ(fitted.cell_shear_replay.break_mismatches, 0);
  EXPECT_LT(fitted.cell_shear_replay.max_error, 1e-9);
  EXPECT_NE(run.fit_output.find("exact law along the fibres (shear): meets 16 one-body antiplane solves"),
            std::string::npos)
      << run.fit_output;
  std::filesystem::copy_file(run.sweep, run.dir / "tampered.h5");
  {
    io::File f = io::File::open_write(run.dir / "tampered.h5");
    std::vector<double> tau = f.read_doubles("/shear_check/tau", {16, 2});
    tau[10] *= 1 + 1e-4;
    f.remove("/shear_check/tau");
    f.write("/shear_check/tau", tau, {16, 2});
  }
  const auto refused = run_command(bin("dualcell-fit") + " --sweep " + q(run.dir / "tampered.h5") + " --out " +
                                   q(run.dir / "tampered-law.h5"));
  EXPECT_EQ(refused.exit_code, exit_input_error) << refused.output;
  EXPECT_NE(refused.output.find("of the shear along the fibres"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(run.dir / "tampered-law.h5"));
  // The flags that do not go with --full: stress-driven, --eps33 beside it, the cone-wise law.
  for (const std::string& flags :
       {std::string(" --stress ") + q(points) + " --full", std::string(" --strain ") + q(points) + " --full --eps33",
        std::string(" --strain ") + q(points) + " --full --form cone"}) {
    const auto bad =
        run_command(bin("dualcell-law") + " --law " + q(run.law) + flags + " --out " + q(run.dir / "bad.csv"));
    EXPECT_EQ(bad.exit_code, exit_input_error) << flags << bad.output;
    EXPECT_FALSE(std::filesystem::exists(run.dir / "bad.csv"));
  }
}

// The stages on a bonded full cell of three directions, without paths held along the fibres
// (plain) and with the [sweep] keys `held` (one more line of that table): each sweep and law. The
// in-plane paths come first in both and are the same to the bit.
struct HeldRuns {
  std::vector<sweep::PathResult> plain, held;
  law::Law plain_law, held_law;
};
HeldRuns held_runs(const std::string& held) {
  const std::string base = testing::scene_text(
      1, 1, 2, 0.3,
      "[interface]\nnormal_strength = 0.02\ntangential_strength = 0.02\n[load]\nboundary = \"periodic\"\nmacro = "
      "\"full\"\n[solver]\ntolerance = 1e-10\n[sweep]\ndirections_deg = [0, 45, 90]\nmagnitudes = [-0.05, "
      "-0.02, 0.02, 0.05]\n");
  HeldRuns out;
  // One scratch folder per run: the plain run's results are read before the other run is made.
  {
    StagesRun plain(base);
    out.plain = io::read_sweep(plain.sweep);
    out.plain_law = io::read_law(plain.law);
  }
  StagesRun run(base + held);
  out.held = io::read_sweep(run.sweep);
  out.held_law = io::read_law(run.law);
  EXPECT_EQ(out.held.size(), 3 * out.plain.size());
  for (std::size_t i = 0; i < out.plain.size() && i < out.held.size(); ++i) {
    EXPECT_TRUE(out.held[i].spec.in_plane());
    EXPECT_EQ(out.held[i].steps.size(), out.plain[i].steps.size()) << i;
    for (std::size_t k = 0; k < out.plain[i].steps.size() && k < out.held[i].steps.size(); ++k)
      EXPECT_EQ(out.held[i].steps[k].strain, out.plain[i].steps[k].strain);
  }
  // The fitted forms see the in-plane paths only: the same numbers.
  EXPECT_EQ(out.held_law.tension.S, out.plain_law.tension.S);
  EXPECT_EQ(out.held_law.cone.law.C_c, out.plain_law.cone.law.C_c);
  return out;
}

// Sweep paths with a strain along the fibres held ([sweep] eps33): each uniaxial path again at
// each ε33, after the others, their steps recording σ33; the in-plane paths and the fitted laws
// are those of the same sweep without them (the same numbers: the fits see in-plane paths only),
// and the exact law replays the ε33 paths too, σ33 included, through the fuse, to the replay's
// limit with the same broken pairs. A transverse scene that asks for them is refused.
// The carbon ply of pipelines/scenes/ply-carbon-epoxy.toml (its fibre the transversely isotropic
// T300 of materials/carbon-epoxy.toml): the fit's E1 is the axial rule of mixtures
// v_f E_L + (1 − v_f) E_m within 1 % (Hill's correction and the mesh's area of the disc are
// far below it), 139.4 GPa, where an isotropic fibre of the transverse modulus gave 10.4; and the
// transverse constants are of a carbon/epoxy ply (E2 between 6 and 12 GPa, G12 between 3 and
// 6 GPa, ν12 between 0.2 and 0.35: the ranges of the ply tables engineers compare with).
TEST(PlyStage, TheCarbonPlysModulusAlongTheFibresIsTheFibres) {
  std::ifstream in(testing::source_dir() + "/pipelines/scenes/ply-carbon-epoxy.toml");
  std::string scene((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The material's path made absolute (the stages run the scene from a scratch folder), in
  // pieces (GCC 12 warns falsely on chains of string concatenation).
  const std::string relative = "../../materials/carbon-epoxy.toml";
  const std::size_t at = scene.find(relative);
  ASSERT_NE(at, std::string::npos);
  std::string absolute = testing::source_dir();
  absolute.append("/materials/carbon-epoxy.toml");
  scene.replace(at, relative.size(), absolute);
  StagesRun run(scene);
  const law::Law law = io::read_law(run.law);
  ASSERT_FALSE(law.ply.rows.empty()) << law.ply.note;
  const law::PlyConstants& bonded = law.ply.rows.front();
  ASSERT_EQ(bonded.state, law::PlyState::bonded);
  const double vf = law.constituents.fibre_volume_fraction;
  EXPECT_NEAR(vf, 0.6, 0.001);
  EXPECT_EQ(law.constituents.fibre_E_L, 230.0);
  const double rule = vf * law.constituents.fibre_E_L + (1 - vf) * law.constituents.matrix_E_L;
  EXPECT_NEAR(bonded.E1, rule, 0.01 * rule);
  EXPECT_GT(bonded.E2, 6);
  EXPECT_LT(bonded.E2, 12);
  EXPECT_GT(bonded.G12, 3);
  EXPECT_LT(bonded.G12, 6);
  EXPECT_GT(bonded.nu12, 0.2);
  EXPECT_LT(bonded.nu12, 0.35);
}

TEST(PlyStage, SweepPathsHoldAStrainAlongTheFibres) {
  const HeldRuns runs = held_runs("eps33 = [-0.002, 0.003]\n");
  const std::vector<sweep::PathResult>&a = runs.plain, &b = runs.held;
  ASSERT_EQ(b.size(), 3 * a.size());
  long broken = 0;
  for (std::size_t i = a.size(); i < b.size(); ++i) {
    EXPECT_EQ(b[i].spec.state.eps33(), i < 2 * a.size() ? -0.002 : 0.003);
    EXPECT_EQ(b[i].spec.direction_deg, b[i - (i < 2 * a.size() ? 1 : 2) * a.size()].spec.direction_deg);
    for (const sweep::Step& step : b[i].steps) {
      EXPECT_TRUE(std::isfinite(step.stress_zz));
      broken = std::max(broken, step.broken_bonds);
    }
  }
  EXPECT_GT(broken, 0) << "the ε33 paths reach past the fuse";
  const law::Law &la = runs.plain_law, &lb = runs.held_law;
  EXPECT_GT(lb.cell_replay.points, 2 * la.cell_replay.points);
  EXPECT_EQ(lb.cell_longitudinal_replay.points, la.cell_longitudinal_replay.points) << "the checks: in-plane paths";
  EXPECT_LE(lb.cell_replay.max_error, lb.cell_replay.limit);
  EXPECT_EQ(lb.cell_replay.break_mismatches, 0);
  testing::ScratchDir dir;
  const auto scene = dir.write("t.toml", testing::scene_text(1, 1, 2, 0.3, "[sweep]\neps33 = [0.001]\n"));
  const auto r = run_command(bin("dualcell-mesh") + " --config " + q(scene) + " --out " + q(dir / "m.h5"));
  EXPECT_EQ(r.exit_code, exit_input_error);
  EXPECT_NE(r.output.find("eps33"), std::string::npos) << r.output;
}

// Paths holding shears Γ along the fibres ([sweep] gamma): each uniaxial path again per Γ, after
// the others, which stay as they were; the full solver runs the antiplane solve beside each QP
// with the same bonds, a tie at its strength breaking its pair (its first step the shear alone).
// The exact law replays them with its cascade: the same pairs broken at every point and ⟨τ⟩ and ε̄
// within the replay's limit (1e3 × the QP tolerance: the sweep's strains carry the QP's error).
// The larger Γ breaks ties by itself, the smaller does not.
TEST(PlyStage, SweepPathsHoldAShearAlongTheFibres) {
  const HeldRuns runs = held_runs("gamma = [[0.05, 0.0], [0.0, -0.001]]\n");
  const std::vector<sweep::PathResult>&a = runs.plain, &b = runs.held;
  ASSERT_EQ(b.size(), 3 * a.size());
  long alone_large = 0, alone_small = 0;
  for (std::size_t i = a.size(); i < b.size(); ++i) {
    const bool large = i < 2 * a.size();
    EXPECT_EQ(b[i].spec.state.gamma(), large ? Eigen::Vector2d(0.05, 0) : Eigen::Vector2d(0, -0.001));
    EXPECT_EQ(b[i].spec.direction_deg, b[i - (large ? 1 : 2) * a.size()].spec.direction_deg);
    ASSERT_FALSE(b[i].steps.empty());
    EXPECT_EQ(b[i].steps[0].load, 0.0);
    (large ? alone_large : alone_small) += b[i].steps[0].broken_bonds;
    for (const sweep::Step& step : b[i].steps) EXPECT_TRUE(step.shear_stress.allFinite());
  }
  EXPECT_GT(alone_large, 0) << "the larger shear breaks ties by itself";
  EXPECT_EQ(alone_small, 0);
  const law::Law &la = runs.plain_law, &lb = runs.held_law;
  EXPECT_GT(lb.cell_replay.points, 2 * la.cell_replay.points);
  EXPECT_LE(lb.cell_replay.max_error, lb.cell_replay.limit);
  EXPECT_EQ(lb.cell_replay.break_mismatches, 0);
  testing::ScratchDir dir;
  const auto scene = dir.write("t.toml", testing::scene_text(1, 1, 2, 0.3,
                                                             "[load]\nboundary = \"periodic\"\nmacro = "
                                                             "\"full\"\n[sweep]\ngamma = [[0.001]]\n"));
  const auto r = run_command(bin("dualcell-mesh") + " --config " + q(scene) + " --out " + q(dir / "m.h5"));
  EXPECT_EQ(r.exit_code, exit_input_error);
  EXPECT_NE(r.output.find("gamma"), std::string::npos) << r.output;
  // The transverse law has no shear along the fibres: a scene asking for it is refused, named.
  const auto transverse = dir.write("u.toml", testing::scene_text(1, 1, 2, 0.3,
                                                                  "[load]\nboundary = \"periodic\"\n[sweep]\n"
                                                                  "gamma = [[0.001, 0]]\n"));
  const auto u = run_command(bin("dualcell-mesh") + " --config " + q(transverse) + " --out " + q(dir / "m.h5"));
  EXPECT_EQ(u.exit_code, exit_input_error);
  EXPECT_NE(u.output.find("macro = \"full\" and boundary = \"periodic\""), std::string::npos) << u.output;
}

}  // namespace
}  // namespace dualcell
