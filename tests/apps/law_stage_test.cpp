// The exact law through the stages: the sweep condenses its cell (/cell), the fit replays the
// sweep through it and measures the compact law against it (/law/cell, /law/cone_check),
// dualcell-law evaluates it at given states, dualcell-export refuses a compact law that misses
// it; and each of them refuses what it must.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/exit_codes.hpp"
#include "core/hash.hpp"
#include "core/strain.hpp"
#include "fit/fit.hpp"
#include "fit/small_cell.hpp"
#include "io/hdf5.hpp"
#include "io/law_export.hpp"
#include "io/law_file.hpp"
#include "io/points_csv.hpp"
#include "io/sweep_file.hpp"
#include "law/condensed.hpp"
#include "law/cone.hpp"
#include "law/reduced.hpp"
#include "stage/sweep.hpp"
#include "stages_run.hpp"
#include "sweep/checks.hpp"
#include "test_util.hpp"

namespace dualcell {
namespace {

using testing::bin;
using testing::q;
using testing::read_csv;
using testing::run_command;
using testing::StagesRun;

// A periodic cell without adhesion swept along three directions and a sphere of 6.
const std::string contact_scene = testing::scene_text(
    1, 1, 2, 0.35,
    "[load]\nboundary = \"periodic\"\n[sweep]\ndirections_deg = [0, 45, 90]\nmagnitudes = [-0.2, 0.2]\nsphere = 6\n"
    "[solver]\ntolerance = 1e-10\n");

// The sweep's own points through dualcell-law, stress-driven and back strain-driven, each path
// with its own path id: the sweep's strains and stresses to the replay's limit.
TEST(LawStage, DualcellLawGivesBackTheSweepInBothDirections) {
  StagesRun run(contact_scene);
  const law::Law law = io::read_law(run.law);
  ASSERT_TRUE(law.cell.has_value()) << law.cell_note;
  EXPECT_TRUE(law.cell_replay.ok());
  EXPECT_EQ(law.cell_replay.points, 12);  // 3 directions × 2 signs and 6 sphere paths, one magnitude each
  EXPECT_EQ(law.cell_replay.break_mismatches, 0);
  // QP tolerance 1e-10: the replay limit is 1e-7, and the sweep's strains carry ≲ 1e-8.
  EXPECT_LE(law.cell_replay.max_error, 1e-7);
  EXPECT_NE(run.fit_output.find("exact law: the cell on"), std::string::npos) << run.fit_output;
  EXPECT_NE(run.fit_output.find("cone-wise law against the exact law at"), std::string::npos);
  EXPECT_GT(law.cone_check.directions.size(), 900u);

  const auto paths = io::read_sweep(run.sweep);
  std::ofstream stress(run.dir / "stress.csv");
  stress << std::setprecision(17) << "path,sxx,syy,sxy\n";
  std::vector<Eigen::Vector3d> strains;
  for (std::size_t p = 0; p < paths.size(); ++p)
    for (const auto& step : paths[p].steps) {
      stress << p << "," << step.stress(0) << "," << step.stress(1) << "," << step.stress(2) << "\n";
      strains.push_back(engineering_from_tensor(step.strain));
    }
  stress.close();
  const auto r = run_command(bin("dualcell-law") + " --law " + q(run.law) + " --stress " + q(run.dir / "stress.csv") +
                             " --out " + q(run.dir / "strain.csv"));
  ASSERT_EQ(r.exit_code, exit_ok) << r.output;
  std::string header;
  const auto rows = read_csv(run.dir / "strain.csv", &header);
  EXPECT_EQ(header, "path,exx,eyy,gxy,C11,C12,C13,C21,C22,C23,C31,C32,C33,broken_pairs");
  ASSERT_EQ(rows.size(), strains.size());
  std::ofstream strain_file(run.dir / "strain_in.csv");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Eigen::Vector3d e(rows[i][1], rows[i][2], rows[i][3]);
    EXPECT_LE((e - strains[i]).norm(), 1e-7 * strains[i].norm()) << i;
    // The tangent is symmetric.
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(rows[i][4 + 3 * a + b], rows[i][4 + 3 * b + a], 1e-9 * rows[i][4]);
    strain_file << std::setprecision(17) << e(0) << "," << e(1) << "," << e(2) << "\n";  // no header, no path
  }
  strain_file.close();
  const auto back = run_command(bin("dualcell-law") + " --law " + q(run.law) + " --strain " +
                                q(run.dir / "strain_in.csv") + " --out " + q(run.dir / "stress_out.csv"));
  ASSERT_EQ(back.exit_code, exit_ok) << back.output;
  const auto stresses = read_csv(run.dir / "stress_out.csv", &header);
  EXPECT_EQ(header.rfind("sxx,syy,sxy,", 0), 0u) << header;
  std::size_t i = 0;
  for (const auto& path : paths)
    for (const auto& step : path.steps) {
      const Eigen::Vector3d s(stresses[i][0], stresses[i][1], stresses[i][2]);
      EXPECT_LE((s - step.stress).norm(), 1e-9 * std::max(step.stress.norm(), 1e-300)) << i;
      ++i;
    }
}

// A law fitted with [load] macro = "full" evaluated with ε33 (dualcell-law --eps33): shortened
// along the fibres at σ̄ = 0 the rims open and the matrix contracts freely, ε̄ = ν_m |ε33| (1, 1, 0)
// exactly (docs/method.md §16a; to the QP's round-off, asked 1e-9); strain-driven at that strain
// the law gives σ̄ = 0 and the same σ33 back. The cone-wise form, which has no ε33, is refused.
TEST(LawStage, DualcellLawEvaluatesTheStrainAlongTheFibres) {
  StagesRun run(testing::scene_text(1, 1, 1, 0.3,
                                    "[load]\nboundary = \"periodic\"\nmacro = \"full\"\n[sweep]\ndirections_deg = [0, "
                                    "90]\nmagnitudes = [-0.1, 0.1]\n[solver]\ntolerance = 1e-10\n"));
  const double e = 1e-3, nu_m = 0.35;  // the matrix of testing::scene_text
  const auto stresses = run.dir.write("s.csv", "sxx,syy,sxy,e33\n0,0,0,-0.001\n0,0,0,0.001\n");
  const auto law = [&](const std::string& args) {
    return run_command(bin("dualcell-law") + " --quiet --law " + q(run.law) + " " + args);
  };
  const auto a = law("--stress " + q(stresses) + " --eps33 --out " + q(run.dir / "a.csv"));
  ASSERT_EQ(a.exit_code, exit_ok) << a.output;
  std::string header;
  const auto rows = read_csv(run.dir / "a.csv", &header);
  EXPECT_EQ(header, "exx,eyy,gxy,szz,C11,C12,C13,C14,C21,C22,C23,C24,C31,C32,C33,C34,C41,C42,C43,C44,broken_pairs");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_NEAR(rows[0][0], nu_m * e, 1e-9 * e);
  EXPECT_NEAR(rows[0][1], nu_m * e, 1e-9 * e);
  // Stretched, the rims close and the stiffer, less contracting fibre holds the matrix back: the
  // ply contracts less than the matrix alone would (the open cell's −ν_m ε33), though it does.
  EXPECT_GT(rows[1][0], -nu_m * e * (1 - 1e-3));
  EXPECT_LT(rows[1][0], 0);
  std::ostringstream back;
  back << std::setprecision(17) << "exx,eyy,gxy,e33\n";
  for (int i = 0; i < 2; ++i)
    back << rows[i][0] << ',' << rows[i][1] << ',' << rows[i][2] << ',' << (i ? e : -e) << '\n';
  const auto strains = run.dir.write("e.csv", back.str());
  const auto b = law("--strain " + q(strains) + " --eps33 --out " + q(run.dir / "b.csv"));
  ASSERT_EQ(b.exit_code, exit_ok) << b.output;
  const auto again = read_csv(run.dir / "b.csv");
  for (int i = 0; i < 2; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(again[i][k], 0, 1e-9 * std::abs(rows[i][3])) << i << " " << k;
    EXPECT_NEAR(again[i][3], rows[i][3], 1e-9 * std::abs(rows[i][3])) << i;
  }
  const auto cone = law("--stress " + q(stresses) + " --eps33 --form cone --out " + q(run.dir / "c.csv"));
  EXPECT_EQ(cone.exit_code, exit_input_error);
  EXPECT_NE(cone.output.find("the cone-wise law has no strain along the fibres"), std::string::npos) << cone.output;
  // An ε33 beyond what doubles carry is named in the message, not only the in-plane part (once
  // "the law's answer at (0, 0, 0)").
  const auto huge = run.dir.write("h.csv", "exx,eyy,gxy,e33\n0,0,0,1e308\n");
  const auto overflow = law("--strain " + q(huge) + " --eps33 --out " + q(run.dir / "h-out.csv"));
  EXPECT_EQ(overflow.exit_code, exit_input_error);
  EXPECT_NE(overflow.output.find("the law's answer at (0, 0, 0), eps33 1e+308 is not finite"), std::string::npos)
      << overflow.output;
}

// A law whose phases expand, swept and fitted without a temperature change (its exact law carries
// ΔT all the same, checked by the fit against the sweep's bonded expansion, docs/theory/model.md
// §1a), evaluated with --delta-T against dualcell-solve of
// the same cell with that [load] delta_T, an independent full solve (its cool-down first, then the
// load, with the bonds' cascade): at zero stress the cooled cell's strain, in transverse tension
// past the onset and in compression with shear; the strain and the broken pairs. Asked 1e-7 of the strain: the solver's
// tolerance 1e-10 amplified by the dual problem's conditioning, as the replay's. The cone-wise
// form refuses --delta-T in one line.
TEST(LawStage, DualcellLawCarriesATemperatureChangeAsTheSolverDoes) {
  std::string scene = testing::scene_text(
      1, 1, 2, 0.35,
      "[load]\nboundary = \"periodic\"\nmacro = \"full\"\n[sweep]\ndirections_deg = [0, 90]\nmagnitudes = [-0.05, "
      "0.05]\n[solver]\ntolerance = 1e-10\n[interface]\nnormal_strength = 0.03\ntangential_strength = 0.03\n");
  scene.replace(scene.find("nu = 0.2\n"), 9, "nu = 0.2\nalpha = 5e-6\n");
  scene.replace(scene.find("nu = 0.35\n"), 10, "nu = 0.35\nalpha = 6e-5\n");
  StagesRun run(scene);
  const law::Law law = io::read_law(run.law);
  ASSERT_TRUE(law.cell.has_value()) << law.cell_note;
  ASSERT_EQ(law.cell->thermal, 1);
  // The fit checked the ΔT column against the sweep's full solves of the bonded expansion.
  EXPECT_EQ(law.cell_thermal_replay.points, 1);
  EXPECT_LE(law.cell_thermal_replay.max_error, law.cell_thermal_replay.limit);
  EXPECT_NE(run.fit_output.find("the bonded expansion meets the sweep's full solves"), std::string::npos)
      << run.fit_output;
  std::string cooled = scene;
  cooled.replace(cooled.find("boundary = \"periodic\"\n"), 22, "boundary = \"periodic\"\ndelta_T = -100\n");
  const auto cooled_scene = run.dir.write("cooled.toml", cooled);
  const std::vector<Eigen::Vector3d> loads = {Eigen::Vector3d::Zero(), {0.06, 0, 0}, {-0.02, 0.005, 0.004}};
  std::ostringstream points;
  points << std::setprecision(17) << "sxx,syy,sxy\n";
  for (const Eigen::Vector3d& s : loads) points << s(0) << ',' << s(1) << ',' << s(2) << '\n';
  const auto stresses = run.dir.write("t.csv", points.str());
  const auto r = run_command(bin("dualcell-law") + " --quiet --law " + q(run.law) + " --stress " + q(stresses) +
                             " --delta-T -100 --out " + q(run.dir / "t-out.csv"));
  ASSERT_EQ(r.exit_code, exit_ok) << r.output;
  const auto rows = read_csv(run.dir / "t-out.csv");
  ASSERT_EQ(rows.size(), loads.size());
  for (std::size_t i = 0; i < loads.size(); ++i) {
    const auto out = run.dir / ("solve" + std::to_string(i) + ".h5");
    std::ostringstream stress;
    stress << std::setprecision(17) << loads[i](0) << ',' << loads[i](1) << ',' << loads[i](2);
    const auto solve = run_command(bin("dualcell-solve") + " --quiet --config " + q(cooled_scene) + " --mesh " +
                                   q(run.dir / "mesh.h5") + " --stress " + stress.str() + " --out " + q(out));
    ASSERT_EQ(solve.exit_code, exit_ok) << solve.output;
    const io::File solved = io::File::open_read(out);
    const auto strain = solved.read_doubles("/macro/strain", {3});
    const auto bonded = solved.read_ints("/interface/bonded", {io::any_extent});
    EXPECT_EQ(rows[i].back(), static_cast<double>(std::count(bonded.begin(), bonded.end(), 0))) << i;
    const Eigen::Vector3d expected = engineering_from_tensor(Eigen::Vector3d(strain[0], strain[1], strain[2]));
    const Eigen::Vector3d got(rows[i][0], rows[i][1], rows[i][2]);
    EXPECT_LE((got - expected).norm(), 1e-7 * expected.norm())
        << i << ": " << got.transpose() << " against " << expected.transpose();
  }
  // The cool-down alone shrinks the cell (the matrix's expansion dominates) and breaks nothing;
  // the transverse tension breaks bonds from it.
  EXPECT_LT(rows[0][0], 0);
  EXPECT_EQ(rows[0].back(), 0);
  EXPECT_GT(rows[1].back(), 0);
  const auto cone = run_command(bin("dualcell-law") + " --quiet --law " + q(run.law) + " --stress " + q(stresses) +
                                " --form cone --delta-T -100 --out " + q(run.dir / "c.csv"));
  EXPECT_EQ(cone.exit_code, exit_input_error);
  EXPECT_NE(cone.output.find("--delta-T: the cone-wise law has no temperature change"), std::string::npos)
      << cone.output;
}

TEST(LawStage, DualcellLawRefusesBadPointsWithTheLine) {
  StagesRun run(contact_scene);
  const auto try_points = [&](const std::string& text, const std::string& flag = " --stress ") {
    const auto points = run.dir.write("p.csv", text);
    return run_command(bin("dualcell-law") + " --law " + q(run.law) + flag + q(points) + " --out " +
                       q(run.dir / "o.csv"));
  };
  const struct {
    const char* text;
    const char* message;
  } cases[] = {
      {"sxx,syy,sxy\n0.1,0,0\n0.1,0\n", "p.csv:3: 2 columns, expected 3 like the first row"},
      {"0.1,0,zero\n", "p.csv:1: column 3 = 'zero' is not a finite number"},
      {"0.1,0,nan\n", "p.csv:1: column 3 = 'nan' is not a finite number"},
      {"a,b\n", "a header of 2 columns"},
      {"name,sxx,syy,sxy\n", "must start with 'path'"},
      {"# nothing\n\n", "p.csv: no rows"},
      // Read and evaluated a row at a time: a bad row after good ones leaves no output either.
      {"0.1,0,0\n0.2,0,0\n0.1,0,x\n", "p.csv:3: column 3 = 'x' is not a finite number"},
  };
  const auto nothing_written = [&] {
    for (const auto& e : std::filesystem::directory_iterator(run.dir.path()))
      if (e.path().filename().string().rfind("o.csv", 0) == 0) return false;
    return true;
  };
  for (const auto& c : cases) {
    const auto r = try_points(c.text);
    EXPECT_EQ(r.exit_code, exit_input_error) << c.text;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.text << " gave " << r.output;
    EXPECT_TRUE(nothing_written()) << c.text;
  }
  // A line beyond io::max_points_line (a 50 MB line of commas took 2.2 GB before its refusal)
  // is refused when its first 4 KiB are read.
  const auto long_line = try_points("0.1,0,0\n" + std::string(io::max_points_line + 1, ','));
  EXPECT_EQ(long_line.exit_code, exit_input_error);
  EXPECT_NE(long_line.output.find("p.csv:2: a line longer than 4096 bytes"), std::string::npos) << long_line.output;
  const std::string at_the_limit = "0.1,0,0" + std::string(io::max_points_line - 7, ' ') + "\n";
  EXPECT_EQ(try_points(at_the_limit).exit_code, exit_ok);
  std::filesystem::remove(run.dir / "o.csv");
  // A file beyond io::max_points_bytes, refused by its size before a line is read (sparse here).
  const auto huge = run.dir.write("huge.csv", "0.1,0,0\n");
  std::filesystem::resize_file(huge, io::max_points_bytes + 1);
  const auto too_big = run_command(bin("dualcell-law") + " --law " + q(run.law) + " --stress " + q(huge) + " --out " +
                                   q(run.dir / "o.csv"));
  EXPECT_EQ(too_big.exit_code, exit_input_error);
  EXPECT_NE(too_big.output.find("more than the 1 GiB a points file may have"), std::string::npos) << too_big.output;
  EXPECT_TRUE(nothing_written());
  const auto missing = run_command(bin("dualcell-law") + " --law " + q(run.law) + " --stress " +
                                   q(run.dir / "none.csv") + " --out " + q(run.dir / "o.csv"));
  EXPECT_NE(missing.output.find("none.csv: no such file"), std::string::npos) << missing.output;
  // C and CSV writers may write a leading +.
  EXPECT_EQ(try_points("+0.001,0,-0.001\n").exit_code, exit_ok);
  std::filesystem::remove(run.dir / "o.csv");
  // An answer that overflows (the cone-wise law at a strain of −1e308 both ways) is an error, not
  // an Inf written with exit 0.
  const auto overflow = try_points("-1e308,-1e308,0\n", " --form cone --strain ");
  EXPECT_EQ(overflow.exit_code, exit_input_error);
  EXPECT_NE(overflow.output.find("p.csv:1: the law's answer at (-1e+308, -1e+308, 0) is not finite"), std::string::npos)
      << overflow.output;
  EXPECT_TRUE(nothing_written());
  const auto neither = run_command(bin("dualcell-law") + " --law " + q(run.law) + " --out " + q(run.dir / "o.csv"));
  EXPECT_EQ(neither.exit_code, exit_input_error);
  EXPECT_NE(neither.output.find("one of --strain and --stress is required"), std::string::npos) << neither.output;
}

// Above fit::max_checked_rows (lowered here to the cell's rows − 1) the exact law is kept and
// replayed, and the compact law is measured on held-out sweep directions instead of the dense
// sphere: the same law fitted, its check from points it was not fitted to.
TEST(LawStage, AboveTheCheckedRowsTheCompactLawIsMeasuredOnHeldOutDirections) {
  StagesRun run(contact_scene);
  const auto paths = io::read_sweep(run.sweep);
  const sweep::SweepHeader header = io::read_sweep_header(run.sweep);
  ASSERT_TRUE(header.cell.has_value());
  const law::Law dense = fit::fit_law(paths, header);
  const law::Law held = fit::fit_law(paths, header, {.checked_rows = header.cell->n_rows() - 1});
  ASSERT_TRUE(held.cell.has_value());
  EXPECT_TRUE(held.cell_replay.ok());
  EXPECT_EQ(dense.cone_check.against, law::CheckedAgainst::exact_law);
  EXPECT_EQ(held.cone_check.against, law::CheckedAgainst::held_out_directions);
  // 3 directions × 2 signs, one magnitude: each held out once; the 6 sphere paths (no direction)
  // are always among the fitted points.
  EXPECT_EQ(held.cone_check.directions.size(), 6u);
  EXPECT_GT(held.cone_check.max_error, 0);
  EXPECT_TRUE(held.cone_check.polar.empty());
}

// Where the exact law is too large to sample (the sweep's and the fit's row limits lowered to 0
// here), the sweep builds the cell on its own solutions (/cell_basis) and the fit fits the small
// cell to the sphere paths' full solves, holding every third path out (150 paths: 50 held out).
// The held-out check is the truth: each recorded error is the small cell's miss against the exact
// law (which the fit never saw) at that direction, to the full solves' tolerance.
TEST(LawStage, AboveTheSampledRowsTheSmallCellIsFittedToFullSolves) {
  testing::ScratchDir dir;
  const auto scene =
      dir.write("s.toml", testing::scene_text(1, 1, 2, 0.35,
                                              "[load]\nboundary = \"periodic\"\n[sweep]\ndirections_deg = [0, 90]\n"
                                              "magnitudes = [-0.2, 0.2]\nsphere = 150\n[solver]\ntolerance = 1e-10\n"));
  ASSERT_EQ(
      run_command(bin("dualcell-mesh") + " --quiet --config " + q(scene) + " --out " + q(dir / "mesh.h5")).exit_code,
      exit_ok);
  stage::SweepOptions options;
  options.scene_file = scene.string();
  options.mesh_file = (dir / "mesh.h5").string();
  options.out = (dir / "sweep.h5").string();
  options.sampled_rows = 0;
  const stage::SweepSummary summary = stage::run_sweep(options);
  ASSERT_TRUE(summary.written);
  const sweep::SweepHeader header = io::read_sweep_header(dir / "sweep.h5");
  ASSERT_TRUE(header.cell && header.cell_basis) << header.cell_basis_note;
  EXPECT_EQ(header.cell_basis->n_rows(), summary.basis_rows);
  EXPECT_GT(summary.basis_rows, 0);
  EXPECT_LE(summary.basis_rows, sweep::basis_solutions);
  EXPECT_EQ(law::consistency_problem(*header.cell_basis), "");

  const law::Law law = fit::fit_law(io::read_sweep(dir / "sweep.h5"), header, {.checked_rows = 0});
  ASSERT_TRUE(law.small) << law.small_note;
  const law::ConeCheck& c = law.small_check;
  EXPECT_EQ(c.against, law::CheckedAgainst::held_out_solves);
  ASSERT_EQ(c.directions.size(), 50u);
  EXPECT_EQ(law.cone_check.against, law::CheckedAgainst::held_out_solves);
  EXPECT_EQ(law.cone_check.directions.size(), 50u);
  // The solves stop at 1e-10 (strain to 1e-7 relative, condense_test's measure); the stress error
  // at the exact strain moves by at most the small cell's stiffness over its softest, ×1e-7.
  law::CellEvaluator exact(*header.cell);
  law::CellSample truth;
  for (const Eigen::Vector3d& N : c.directions) {
    law::CellHistory h = exact.unloaded();
    const law::CellResponse r = exact.at_stress(N, h);
    ASSERT_TRUE(r.ok) << r.message;
    truth.direction.push_back(N);
    truth.strain.push_back(r.strain);
    truth.stress.push_back(N);
  }
  const law::ConeCheck against_exact = law::check_reduced(*law.small, truth);
  for (std::size_t i = 0; i < c.directions.size(); ++i) EXPECT_NEAR(c.error[i], against_exact.error[i], 1e-5) << i;

  // Fewer sphere paths than two checks' worth: no basis is solved for, and the fit falls back to
  // the held-out sweep directions.
  const auto few =
      dir.write("few.toml", testing::scene_text(1, 1, 2, 0.35,
                                                "[load]\nboundary = \"periodic\"\n[sweep]\ndirections_deg = [0, 90]\n"
                                                "magnitudes = [-0.2, 0.2]\nsphere = " +
                                                    std::to_string(2 * fit::min_held_out - 1) + "\n"));
  options.scene_file = few.string();
  options.out = (dir / "few.h5").string();
  ASSERT_TRUE(stage::run_sweep(options).written);
  const sweep::SweepHeader without = io::read_sweep_header(dir / "few.h5");
  EXPECT_FALSE(without.cell_basis);
  EXPECT_EQ(fit::fit_law(io::read_sweep(dir / "few.h5"), without, {.checked_rows = 0}).cone_check.against,
            law::CheckedAgainst::held_out_directions);
}

// A compact law that misses the exact one is not exported as a umat, with the error and where;
// --force writes it; a generous limit lets it through.
TEST(LawStage, ExportRefusesACompactLawThatMissesTheExactOne) {
  StagesRun run(contact_scene);
  const law::Law law = io::read_law(run.law);
  ASSERT_FALSE(law.cone_check.directions.empty());
  ASSERT_GT(law.cone_check.max_error, 0.02) << "this cell's cone-wise law misses by more than 2 %";
  const std::string export_umat =
      bin("dualcell-export") + " --law " + q(run.law) + " --format umat --form cone --out " + q(run.dir / "u.inp");
  const auto refused = run_command(export_umat);
  EXPECT_EQ(refused.exit_code, exit_input_error);
  EXPECT_NE(refused.output.find("the cone-wise law misses the exact law by"), std::string::npos) << refused.output;
  // No small cell, so no tolerance it was fitted to: the default limit, named so.
  EXPECT_NE(refused.output.find("more than the default tolerance 2 %"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(run.dir / "u.inp"));
  EXPECT_EQ(run_command(export_umat + " --force").exit_code, exit_ok);
  EXPECT_EQ(run_command(export_umat + " --max-law-error 0.99").exit_code, exit_ok);
}

// With adhesion the law past the fuse is measured too (/law/cone_after_fuse_check): the recorded
// error at the worst direction is what the exact law along that path (40 steps through its
// cascade) and the compact law past the fuse give, computed here without the fit's code; the
// summary prints it, the JSON carries it, and a umat whose law past the fuse misses by more
// than --max-law-error is refused although the bonded law (linear: exact) passes.
TEST(LawStage, TheLawPastTheFuseIsMeasuredAndItsErrorRefusesTheUmat) {
  StagesRun run(testing::scene_text(
      1, 1, 2, 0.35,
      "[interface]\nnormal_strength = 0.02\ntangential_strength = 0.02\n[load]\nboundary = \"periodic\"\n"
      "[sweep]\ndirections_deg = [0, 45, 90]\nmagnitudes = [-0.2, -0.1, 0.02, 0.05, 0.1, 0.2]\n"));
  const law::Law law = io::read_law(run.law);
  ASSERT_TRUE(law.cell.has_value()) << law.cell_note;
  ASSERT_TRUE(law.cone_after_fuse.ok) << law.cone_after_fuse.message;
  const law::ConeCheck& c = law.cone_after_fuse_check;
  ASSERT_GT(c.directions.size(), 250u);
  EXPECT_NE(run.fit_output.find("cone-wise law after the fuse against the exact law at twice its onset"),
            std::string::npos)
      << run.fit_output;
  law::CellEvaluator evaluator(*law.cell);
  const double onset = evaluator.onset(c.worst);
  law::CellHistory h = evaluator.unloaded();
  law::CellResponse r;
  for (int step = 1; step <= 40; ++step) r = evaluator.at_stress(step / 20.0 * onset * c.worst, h);
  ASSERT_TRUE(r.ok) << r.message;
  const Eigen::Vector3d sigma = 2 * onset * c.worst;
  const double error = (law::evaluate(law.cone_after_fuse.law, r.strain).stress - sigma).norm() / sigma.norm();
  EXPECT_NEAR(error, c.max_error, 1e-6) << "the recorded error is the compact law's miss at that state";
  EXPECT_GT(c.max_error, 0.02) << "this cell's law past the fuse misses by more than 2 %";
  EXPECT_LT(law.cone_check.max_error, 1e-6) << "bonded, the cell is linear and the compact law exact";

  const auto json =
      run_command(bin("dualcell-export") + " --law " + q(run.law) + " --format json --out " + q(run.dir / "law.json"));
  ASSERT_EQ(json.exit_code, exit_ok) << json.output;
  std::ifstream in(run.dir / "law.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"cone_after_fuse_check\""), std::string::npos);

  const std::string export_umat =
      bin("dualcell-export") + " --law " + q(run.law) + " --format umat --form cone --out " + q(run.dir / "u.inp");
  const auto refused = run_command(export_umat);
  EXPECT_EQ(refused.exit_code, exit_input_error);
  EXPECT_NE(refused.output.find("the cone-wise law after the fuse misses the exact law by"), std::string::npos)
      << refused.output;
  EXPECT_FALSE(std::filesystem::exists(run.dir / "u.inp"));
  EXPECT_EQ(run_command(export_umat + " --force").exit_code, exit_ok);
}

// The JSON export carries the exact law and its checks, the same numbers as law.h5 (17 digits);
// an unbounded row's bound is null.
// The exact law's umat is two files, the card naming the cell file by its id and its hash. The
// same law again under the same id rewrites the same file; another cell under that id is refused
// (a card written before names the file there), unless --force.
TEST(LawStage, ExportKeepsACellFileThatAnotherCardNames) {
  StagesRun run(contact_scene);
  const std::string export_cell = bin("dualcell-export") + " --law " + q(run.law) + " --format umat --form cell --out ";
  ASSERT_EQ(run_command(export_cell + q(run.dir / "a.inp")).exit_code, exit_ok);
  const auto cell_file = run.dir / "dualcell-cell-1.txt";
  ASSERT_TRUE(std::filesystem::exists(cell_file));
  EXPECT_EQ(run_command(export_cell + q(run.dir / "b.inp")).exit_code, exit_ok) << "the same cell: the same file";
  run.dir.write("dualcell-cell-1.txt", "another cell\n");
  const auto refused = run_command(export_cell + q(run.dir / "c.inp"));
  EXPECT_EQ(refused.exit_code, exit_input_error);
  EXPECT_NE(refused.output.find("dualcell-cell-1.txt: holds another cell"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(run.dir / "c.inp"));
  std::ifstream kept(cell_file);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(kept)), std::istreambuf_iterator<char>()), "another cell\n");
  // A rerun replaces the card that names the file together with the file: allowed.
  run.dir.write("rerun.inp",
                "** a card\n2, 1, 1, 1, 1, " + io::umat_cell_hash_constants(text_hash_value("another cell\n")) + "\n");
  EXPECT_EQ(run_command(export_cell + q(run.dir / "rerun.inp")).exit_code, exit_ok);
  run.dir.write("dualcell-cell-1.txt", "another cell\n");
  EXPECT_EQ(run_command(export_cell + q(run.dir / "c.inp") + " --force").exit_code, exit_ok);
  EXPECT_EQ(run_command(export_cell + q(run.dir / "d.inp") + " --cell-id 2").exit_code, exit_ok);
  // A fraction, finite: CLI::Range alone let NaN through.
  const auto nan_bound = run_command(export_cell + q(run.dir / "e.inp") + " --max-law-error nan");
  EXPECT_NE(nan_bound.exit_code, exit_ok);
  EXPECT_NE(nan_bound.output.find("--max-law-error: 'nan' is not a finite number"), std::string::npos)
      << nan_bound.output;
  EXPECT_NE(run_command(export_cell + q(run.dir / "e.inp") + " --max-law-error 2").exit_code, exit_ok);
  EXPECT_FALSE(std::filesystem::exists(run.dir / "e.inp"));
}

TEST(LawStage, TheJsonExportCarriesTheExactLaw) {
  StagesRun run(contact_scene);
  const law::Law law = io::read_law(run.law);
  ASSERT_TRUE(law.cell.has_value());
  const auto r =
      run_command(bin("dualcell-export") + " --law " + q(run.law) + " --format json --out " + q(run.dir / "law.json"));
  ASSERT_EQ(r.exit_code, exit_ok) << r.output;
  const law::CondensedCell& c = *law.cell;
  std::ostringstream script;
  script.precision(17);
  script << "import json, sys\n"
         << "d = json.load(open(sys.argv[1]))\n"
         << "c = d['cell']\n"
         << "assert len(c['H']) == " << c.n_rows() << " and len(c['H'][0]) == " << c.n_rows() << "\n"
         << "assert c['H'][1][2] == " << c.H(1, 2) << " and c['S0'][0][1] == " << c.S0(0, 1) << "\n"
         << "assert c['Y'][3][2] == " << c.Y(3, 2) << " and c['n_pairs'] == " << c.n_pairs << "\n"
         << "assert None in c['upper_broken'] and c['lower_broken'][0] == 0\n"
         << "assert d['cell_replay']['points'] == " << law.cell_replay.points << "\n"
         << "assert d['cone_check']['directions'] == " << law.cone_check.directions.size() << "\n"
         << "assert d['cone_check']['max_error'] == " << law.cone_check.max_error << "\n";
  std::ofstream(run.dir / "check.py") << script.str();
  const auto checked = run_command("/usr/bin/python3 " + q(run.dir / "check.py") + " " + q(run.dir / "law.json"));
  EXPECT_EQ(checked.exit_code, 0) << checked.output << script.str();
}

// A condensation that does not give back the sweep is refused by the fit, and nothing is written.
TEST(LawStage, FitRefusesAnExactLawThatMissesItsSweep) {
  StagesRun run(contact_scene);
  sweep::SweepHeader header = io::read_sweep_header(run.sweep);
  ASSERT_TRUE(header.cell.has_value());
  header.cell->Y *= 1.001;  // the openings per unit stress off by 0.1 %
  io::write_sweep(run.dir / "wrong.h5", io::read_sweep(run.sweep), header);
  const auto r = run_command(bin("dualcell-fit") + " --sweep " + q(run.dir / "wrong.h5") + " --out " +
                             q(run.dir / "wrong-law.h5"));
  EXPECT_EQ(r.exit_code, exit_input_error) << r.output;
  EXPECT_NE(r.output.find("the exact law misses the sweep's point"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(run.dir / "wrong-law.h5"));
}

}  // namespace
}  // namespace dualcell

namespace dualcell {
namespace {

// The small cell through the stages: a cell this small (32 rows) gets none and says why, and
// --form small is refused with that reason; a law.h5 given one (fitted here, 4 rows) is
// evaluated by dualcell-law as the library evaluates it, and exported to the umat as a cell,
// refused while its measured error is over --max-law-error.
TEST(LawStage, TheSmallCellGoesThroughLawAndExport) {
  StagesRun run(contact_scene);
  law::Law law = io::read_law(run.law);
  ASSERT_TRUE(law.cell);
  EXPECT_FALSE(law.small);
  EXPECT_NE(law.small_note.find("rows: it costs what a small cell would"), std::string::npos) << law.small_note;
  EXPECT_NE(run.fit_output.find("small cell: none"), std::string::npos) << run.fit_output;
  const auto points = run.dir.write("e.csv", "exx,eyy,gxy\n0.01,-0.02,0.005\n-0.01,-0.01,0.02\n");
  const std::string evaluate = bin("dualcell-law") + " --quiet --strain " + q(points) + " --form small --out ";
  const auto none = run_command(evaluate + q(run.dir / "v.csv") + " --law " + q(run.law));
  EXPECT_EQ(none.exit_code, exit_input_error);
  EXPECT_NE(none.output.find("/law/small: no small cell (the exact law has"), std::string::npos) << none.output;
  const auto no_umat = run_command(bin("dualcell-export") + " --law " + q(run.law) +
                                   " --format umat --form small --out " + q(run.dir / "u.inp"));
  EXPECT_EQ(no_umat.exit_code, exit_input_error);
  EXPECT_NE(no_umat.output.find("/law/small: no small cell"), std::string::npos) << no_umat.output;

  const law::CellSample training = law::sample_cell(*law.cell, 200), check = law::sample_cell(*law.cell, 300);
  fit::SmallCellOptions options;
  options.rows = 4;
  const fit::SmallCell small = fit::fit_small_cell(*law.cell, training, options);
  ASSERT_TRUE(small.ok) << small.message;
  law.small = small.cell;
  law.small_check = law::check_reduced(small.cell, check);
  ASSERT_GT(law.small_check.max_error, 0.02) << "4 rows miss this cell by more than 2 %";
  const auto with_small = run.dir / "small.h5";
  io::write_law(with_small, law);
  const auto r = run_command(evaluate + q(run.dir / "v.csv") + " --law " + q(with_small));
  ASSERT_EQ(r.exit_code, exit_ok) << r.output;
  const auto rows = read_csv(run.dir / "v.csv");
  ASSERT_EQ(rows.size(), 2u);
  law::CellEvaluator evaluator(*law.small);
  law::CellHistory h = evaluator.unloaded();
  const law::CellResponse first = evaluator.at_strain(Eigen::Vector3d(0.01, -0.02, 0.005), h);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rows[0][k], first.stress(k), 1e-12 * first.stress.norm()) << k;
  const std::string export_umat = bin("dualcell-export") + " --law " + q(with_small) +
                                  " --format umat --form small --cell-id 4 --out " + q(run.dir / "u.inp");
  const auto refused = run_command(export_umat);
  EXPECT_EQ(refused.exit_code, exit_input_error);
  EXPECT_NE(refused.output.find("the small cell misses the exact law by"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(run.dir / "u.inp"));
  const auto forced = run_command(export_umat + " --force");
  ASSERT_EQ(forced.exit_code, exit_ok) << forced.output;
  EXPECT_NE(forced.output.find("the small cell (4 rows)"), std::string::npos) << forced.output;
  std::ifstream card_file(run.dir / "u.inp");
  const std::string card((std::istreambuf_iterator<char>(card_file)), std::istreambuf_iterator<char>());
  EXPECT_NE(card.find("small cell fitted to the exact law (4 rows"), std::string::npos) << card;
  EXPECT_TRUE(std::filesystem::exists(run.dir / "dualcell-cell-4.txt"));
  // A law fitted to a looser tolerance (dualcell-fit --law-tolerance) is exported by default
  // within it, and refused by an explicit --max-law-error below its error (the export once held
  // every law to its own 2 %).
  law.small_fit.tolerance = 2 * law.small_check.max_error;
  const auto looser = run.dir / "looser.h5";
  io::write_law(looser, law);
  const std::string export_looser = bin("dualcell-export") + " --law " + q(looser) +
                                    " --format umat --form small --cell-id 5 --out " + q(run.dir / "l.inp");
  const auto within = run_command(export_looser);
  EXPECT_EQ(within.exit_code, exit_ok) << within.output;
  const auto told = run_command(export_looser + " --max-law-error 0.02");
  EXPECT_EQ(told.exit_code, exit_input_error) << told.output;
  EXPECT_NE(told.output.find("more than --max-law-error 2 %"), std::string::npos) << told.output;
  const auto over = run_command(bin("dualcell-export") + " --law " + q(with_small) +
                                " --format umat --form small --cell-id 6 --out " + q(run.dir / "o.inp"));
  EXPECT_NE(over.output.find("more than the default tolerance 2 %"), std::string::npos) << over.output;

  // law.json mirrors law.h5: every object of /law (and the root's attributes) has its key, the
  // small cell, its fit and its check included (once left out), and the cells' members and the
  // fit's fields by the same names.
  ASSERT_EQ(run_command(bin("dualcell-export") + " --quiet --law " + q(looser) + " --format json --out " +
                        q(run.dir / "law.json"))
                .exit_code,
            exit_ok);
  const std::string mirror =
      "import h5py, json, sys\n"
      "f = h5py.File(sys.argv[1], 'r'); d = json.load(open(sys.argv[2]))\n"
      "law = f['/law']\n"
      "h5 = set(law.keys()) | set(law.attrs.keys()) | set(f['/'].attrs.keys())\n"
      "assert h5 == set(d.keys()), ('only in law.h5', sorted(h5 - set(d)), 'only in law.json', sorted(set(d) - h5))\n"
      "for g in ('cell', 'small', 'small_fit'):\n"
      "    h = set(law[g].keys()) | set(law[g].attrs.keys())\n"
      "    assert h <= set(d[g].keys()), (g, sorted(h - set(d[g])))\n"
      "assert len(d['small']['Y']) == 4 and d['small_check']['max_error'] > 0.02\n"
      "print('mirrors')\n";
  const auto mirrored = run_command("/usr/bin/python3 " + q(run.dir.write("mirror.py", mirror)) + " " + q(looser) +
                                    " " + q(run.dir / "law.json"));
  EXPECT_EQ(mirrored.output, "mirrors\n") << mirrored.output;
}

}  // namespace
}  // namespace dualcell
