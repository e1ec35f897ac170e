// The compact cone-wise law fitted to the exact law (fit::fit_cone_to_cell) keeps the symmetries
// the cell has, measured on the exact law, exactly: a centred fibre's cell maps x ↔ y onto itself
// (the mapped mesh's diagonals keep that mirror), so the law's E(0°) equals its E(90°); an
// off-centre fibre has none, and the fit imposes none. The law is admissible and convex by
// construction, and it is no worse than its own sample says.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "fit/cone_fit.hpp"
#include "law/cone_check.hpp"
#include "mesh/mesh.hpp"
#include "test_util.hpp"

namespace dualcell::fit {
namespace {

law::CondensedCell contact_cell(const Eigen::Vector2d& offset) {
  Scene s = parse_scene(testing::scene_text(1, 1, 2, 0.3), "test.toml");
  s.geometry.element = Element::p2;
  s.geometry.fibre_offset = {offset.x(), offset.y()};
  s.fibre = {30.0, 0.22};
  s.matrix = {1.0, 0.35};
  s.load.boundary = Boundary::periodic;
  s.interface.normal_strength = s.interface.tangential_strength = 0;
  const mesh::Mesh mesh = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(mesh, s);
  return feti::condense(solver.setup());
}

TEST(ConeToCell, TheCompactLawHasTheCellsSymmetriesExactly) {
  Eigen::Matrix3d swap;
  swap << 0, 1, 0, 1, 0, 0, 0, 0, 1;
  for (const bool centred : {true, false}) {
    SCOPED_TRACE(centred ? "centred fibre" : "off-centre fibre");
    const law::CondensedCell cell = contact_cell(centred ? Eigen::Vector2d::Zero() : Eigen::Vector2d(0.07, -0.04));
    const law::ConeFit fit = fit_cone_to_cell(cell, {}, 0, 400);
    ASSERT_TRUE(fit.ok) << fit.message;
    EXPECT_EQ(law::admissibility_problem(fit.law), "");
    if (!centred) {
      EXPECT_NE(fit.form.find(", 1 symmetries"), std::string::npos) << fit.form;
      continue;
    }
    EXPECT_EQ(fit.form.find(", 1 symmetries"), std::string::npos) << fit.form;
    std::mt19937 rng(5);
    std::normal_distribution<double> g;
    for (int i = 0; i < 50; ++i) {
      const Eigen::Vector3d e(g(rng), g(rng), g(rng));
      const Eigen::Vector3d s = law::evaluate(fit.law, e).stress;
      EXPECT_LE((law::evaluate(fit.law, swap * e).stress - swap * s).norm(), 1e-12 * s.norm()) << e.transpose();
    }
    for (const double sign : {1.0, -1.0})
      EXPECT_NEAR(law::apparent_modulus(fit.law, 0, sign), law::apparent_modulus(fit.law, 90, sign),
                  1e-12 * law::apparent_modulus(fit.law, 0, sign));
    // Measured on another sample of the exact law: what the fit promises is what it does.
    const law::ConeCheck check = law::check_cone(fit.law, law::sample_cell(cell, 300));
    EXPECT_LT(check.rms_error, 0.1);
  }
}

}  // namespace
}  // namespace dualcell::fit
