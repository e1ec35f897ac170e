// sweep.h5 written and read back (io/sweep_file.hpp): every column of io::step_columns and every
// field of io::fuse_fields, the paths' specs, and the header (provenance, constituents, the onset
// surface, the exact law, the QP tolerance) come back as written, bit for bit. The paths are a
// real sweep's (adhesion, so a fuse and an onset), with one step marked unconverged; the test
// walks the tables, so a column added to them is checked without an edit here.
#include "io/sweep_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "io/record_walk.hpp"
#include "sweep/sweep.hpp"
#include "test_util.hpp"

namespace dualcell::io {
namespace {

// Equal as doubles, NaN equal to NaN (the file keeps NaN where a value is undetermined).
bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }
bool same(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return same(a(0), b(0)) && same(a(1), b(1)) && same(a(2), b(2));
}

struct Written {
  std::vector<sweep::PathResult> paths;
  SweepHeader header;
};

Written sweep_of_a_cell_with_adhesion() {
  Scene scene = parse_scene(testing::scene_text(1, 1, 1, 0.3,
                                                "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n"
                                                "[load]\nboundary = \"periodic\"\n"
                                                "[sweep]\ndirections_deg = [0, 90]\nmagnitudes = [-0.2, 0.2]\n"),
                            "test.toml");
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  feti::ContactSolver solver(mesh, scene);
  Written w;
  for (const sweep::PathSpec& spec : sweep::plan_paths(scene))
    w.paths.push_back(sweep::run_path(solver, spec, scene.sweep.fuse_tolerance));
  w.paths.front().steps.back().converged = false;  // the flag column must come back as 0
  // Every text of the provenance, each its own (the reader needs those a sweep always has).
  testing::set_each_field(provenance_fields, w.header.provenance);
  w.header.provenance.solver_options = solver_options_text(scene);
  w.header.constituents = constituents(scene);
  w.header.onset = solver.onset_surface();
  w.header.cell = feti::condense(solver.setup());
  w.header.cell_note = "a note";
  w.header.qp_tolerance = scene.solver.tolerance;
  return w;
}

TEST(SweepFile, EveryColumnAndTheHeaderComeBackAsWritten) {
  const Written w = sweep_of_a_cell_with_adhesion();
  ASSERT_TRUE(w.paths.front().fuse.has_value()) << "the test needs a path through the fuse";
  testing::ScratchDir dir;
  const auto file = dir / "sweep.h5";
  write_sweep(file, w.paths, w.header);
  const std::vector<sweep::PathResult> back = read_sweep(file);
  ASSERT_EQ(back.size(), w.paths.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    const sweep::PathResult &a = w.paths[i], &b = back[i];
    EXPECT_EQ(b.spec.sign, a.spec.sign) << i;
    EXPECT_TRUE(same(b.spec.direction_deg, a.spec.direction_deg)) << i;
    EXPECT_TRUE(same(b.spec.state.in_plane(), a.spec.state.in_plane())) << i;
    EXPECT_EQ(b.spec.loads, a.spec.loads) << i;
    ASSERT_EQ(b.steps.size(), a.steps.size()) << i;
    for (std::size_t k = 0; k < a.steps.size(); ++k)
      testing::expect_same_fields(step_columns, a.steps[k], b.steps[k],
                                  "path " + std::to_string(i) + " step " + std::to_string(k));
    ASSERT_EQ(b.fuse.has_value(), a.fuse.has_value()) << i;
    if (!a.fuse) continue;
    testing::expect_same_fields(fuse_fields, *a.fuse, *b.fuse, "path " + std::to_string(i) + " fuse");
  }
  EXPECT_FALSE(back.front().steps.back().converged);

  const SweepHeader h = read_sweep_header(file);
  testing::expect_same_fields(provenance_fields, h.provenance, w.header.provenance, "provenance");
  testing::expect_same_fields(constituent_fields, h.constituents, w.header.constituents, "constituents");
  EXPECT_EQ(h.onset.facets, w.header.onset.facets);
  EXPECT_EQ(h.onset.pair, w.header.onset.pair);
  EXPECT_EQ(h.onset.tangential, w.header.onset.tangential);
  EXPECT_EQ(h.onset.linear, w.header.onset.linear);
  ASSERT_TRUE(h.cell.has_value());
  EXPECT_EQ(h.cell->H, w.header.cell->H);
  EXPECT_EQ(h.cell->Y, w.header.cell->Y);
  EXPECT_EQ(h.cell->S0, w.header.cell->S0);
  EXPECT_EQ(h.cell->G, w.header.cell->G);
  EXPECT_EQ(h.cell_note, w.header.cell_note);
  EXPECT_EQ(h.qp_tolerance, w.header.qp_tolerance);
}

// NaN in the newer datasets is refused on reading, as in the older ones: a converged step's stress
// along the fibres (a path with eps33) or shear stresses (a path with gamma), and any number of
// the checks along the fibres (/longitudinal_check, /shear_check). (The fit once replayed an
// all-NaN stress_zz "to max 9.6e-08", dropped a step with a NaN shear stress and the exact law
// with a NaN check, each with exit 0.)
TEST(SweepFile, NotANumberInTheNewerDatasetsIsRefused) {
  const Written w = sweep_of_a_cell_with_adhesion();
  testing::ScratchDir dir;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto refused = [&](std::vector<sweep::PathResult> paths, SweepHeader header, const std::string& expected) {
    const auto file = dir / "sweep.h5";
    std::filesystem::remove(file);
    write_sweep(file, paths, header);
    std::string error;
    try {
      read_sweep_header(file);
      read_sweep(file);
    } catch (const InputError& e) {
      error = e.what();
    }
    EXPECT_NE(error.find(expected), std::string::npos) << "'" << error << "', expected '" << expected << "'";
  };
  std::vector<sweep::PathResult> along = w.paths;
  along[0].spec.state.hold(MacroState::zz, 1e-3);
  for (sweep::Step& step : along[0].steps) step.stress_zz = 0.1;
  along[0].steps[1].stress_zz = nan;
  refused(along, w.header, "/stress_zz: non-finite stress in converged row 1");
  std::vector<sweep::PathResult> sheared = w.paths;
  sheared[1].spec.state.hold_shear(Eigen::Vector2d(1e-3, 0));
  for (sweep::Step& step : sheared[1].steps) step.shear_stress = Eigen::Vector2d(0.1, 0);
  sheared[1].steps[2].shear_stress(1) = nan;
  refused(sheared, w.header, "/shear_stress: non-finite stress in converged row 2");
  SweepHeader checks = w.header;
  checks.longitudinal_points = {{Eigen::Vector3d(0.1, 0, 0), 1e-3, Eigen::Vector3d(0.01, 0, 0), 0.2, 0},
                                {Eigen::Vector3d(0.1, 0, 0), 1e-3, Eigen::Vector3d(0.01, 0, 0), nan, 0}};
  refused(w.paths, checks, "/longitudinal_check/stress_zz: non-finite value in row 1");
  checks.longitudinal_points.clear();
  checks.shear_points = {{0, Eigen::Vector2d(1e-3, 0), Eigen::Vector2d(nan, 0), 0}};
  refused(w.paths, checks, "/shear_check/tau: non-finite value in row 0");
}

}  // namespace
}  // namespace dualcell::io
