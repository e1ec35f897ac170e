// The exact law of a cell (docs/method.md §16a) against the full dual solve of the same cell at
// stress directions that no condensation step saw, and against its own algebra.
#include "feti/condense.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "core/error.hpp"
#include "core/strain.hpp"
#include "feti/constraints.hpp"
#include "feti/solver.hpp"
#include "law/reduced.hpp"
#include "sweep/sweep.hpp"
#include "test_util.hpp"

namespace dualcell::feti {
namespace {

// The full solver stops at a relative projected gradient of 1e-10; its macro strain carries that
// error amplified by the conditioning of the dual problem (≈ 1e2 for these meshes): 1e-7
// relative leaves an order of margin. The law's own evaluations are exact to round-off (1e-11).
constexpr double against_solver = 1e-7;
constexpr double round_off = 1e-11;

Scene cell_scene(Boundary boundary, Element element, int ex, int ey, double strength, int degree = 2) {
  Scene s = parse_scene(testing::scene_text(ex, ey, degree, 0.3), "test.toml");
  s.geometry.element = element;
  s.fibre = {30.0, 0.22};
  s.matrix = {1.0, 0.35};
  s.load.boundary = boundary;
  s.interface.normal_strength = strength;
  s.interface.tangential_strength = strength;
  s.solver.tolerance = 1e-10;
  return s;
}

// v without its shear where the cell has none (the symmetry boundary: NaN there).
Eigen::Vector3d in_plane(Eigen::Vector3d v, bool shear) {
  if (!shear) v(2) = 0;
  return v;
}
Eigen::Matrix3d in_plane(Eigen::Matrix3d C, bool shear) {
  if (!shear) C.row(2).setZero(), C.col(2).setZero();
  return C;
}

// Directions with all three components (two only for the symmetry boundary), not on any axis.
std::vector<Eigen::Vector3d> directions(int n, bool shear, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < n; ++i) out.push_back(Eigen::Vector3d(g(rng), g(rng), shear ? g(rng) : 0.0).normalized());
  return out;
}

struct Case {
  Boundary boundary;
  Element element;
  int ex, ey;
};

class CondensedContact : public ::testing::TestWithParam<Case> {};

INSTANTIATE_TEST_SUITE_P(Cells, CondensedContact,
                         ::testing::Values(Case{Boundary::periodic, Element::p2, 1, 1},
                                           Case{Boundary::periodic, Element::p1, 2, 1},
                                           Case{Boundary::traction, Element::p2, 1, 1},
                                           Case{Boundary::symmetry, Element::p2, 2, 2}),
                         [](const auto& info) {
                           const Case& c = info.param;
                           return std::string(to_string(c.boundary)) + "_" + to_string(c.element) + "_" +
                                  std::to_string(c.ex) + "x" + std::to_string(c.ey);
                         });

// Without adhesion: the law's strain for a stress equals the full solve's, at directions
// drawn at random; the strain-driven law inverts it; the tangent is the derivative.
TEST_P(CondensedContact, ReproducesTheCellAtDirectionsItNeverSaw) {
  const Case c = GetParam();
  const Scene scene = cell_scene(c.boundary, c.element, c.ex, c.ey, 0.0);
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  ContactSolver solver(mesh, scene);
  const law::CondensedCell cell = condense(solver.setup());
  EXPECT_EQ(law::consistency_problem(cell), "");
  // Reciprocity holds to the round-off of the elimination (measured 1e-13 … 1e-11).
  EXPECT_LE(cell.reciprocity_error, 1e-9);
  EXPECT_FALSE(cell.adhesion());
  const bool shear = c.boundary != Boundary::symmetry;
  EXPECT_EQ(cell.n_macro, shear ? 3 : 2);

  law::CellEvaluator law(cell);
  for (const Eigen::Vector3d& sigma : directions(6, shear, 7)) {
    const Solution s = solver.solve(sigma, solver.intact());
    ASSERT_TRUE(s.converged());
    law::CellHistory h = law.unloaded();
    const law::CellResponse r = law.at_stress(sigma, h);
    ASSERT_TRUE(r.ok) << r.message;
    const Eigen::Vector3d strain = in_plane(r.strain, shear),
                          expected = in_plane(engineering_from_tensor(s.strain), shear);
    const Eigen::Matrix3d tangent = in_plane(r.tangent, shear);
    EXPECT_LE((strain - expected).norm(), against_solver * expected.norm()) << sigma.transpose();
    EXPECT_EQ(r.broken, 0);

    // Strain-driven at that strain: the same stress back, with the same tangent.
    law::CellHistory h2 = law.unloaded();
    const law::CellResponse back = law.at_strain(strain, h2);
    ASSERT_TRUE(back.ok) << back.message;
    EXPECT_LE((back.stress - sigma).norm(), 1e2 * round_off) << sigma.transpose();
    EXPECT_LE((in_plane(back.tangent, shear) - tangent).norm(), 1e-8 * tangent.norm());

    // Positively homogeneous of degree one: no adhesion, a cone.
    law::CellHistory h3 = law.unloaded();
    const Eigen::Vector3d twice = in_plane(law.at_stress(2.5 * sigma, h3).strain, shear);
    EXPECT_LE((twice - 2.5 * strain).norm(), 1e2 * round_off * strain.norm());

    // The tangent against central differences of the strain-driven law (piecewise linear: exact
    // inside a piece; the step 1e-7 of |ε̄| stays inside it unless a row switches within it).
    const double step = 1e-7 * strain.norm();
    for (int k = 0; k < cell.n_macro; ++k) {
      law::CellHistory hp = law.unloaded(), hm = law.unloaded();
      const Eigen::Vector3d plus = law.at_strain(strain + step * Eigen::Vector3d::Unit(k), hp).stress;
      const Eigen::Vector3d minus = law.at_strain(strain - step * Eigen::Vector3d::Unit(k), hm).stress;
      const Eigen::Vector3d column = (plus - minus) / (2 * step);
      EXPECT_LE((column - tangent.col(k)).norm(), 1e-6 * tangent.norm()) << k;
    }
  }
}

// The cell on a basis of its own solutions, formed from F's applications (condense_on_solutions),
// is the exact law restricted to the same basis (law::cell_on_basis of the dense condensation):
// two routes through different algebra (columns of F applied as an operator against F summed from
// the subdomains' blocks), equal to the round-off of the eliminations (measured ≤ 1e-12). Along
// every direction whose solution is a column the basis cell is the cell: its strain is the full
// solve's.
TEST_P(CondensedContact, OnItsOwnSolutionsIsTheExactLawOnThatBasis) {
  const Case c = GetParam();
  const Scene scene = cell_scene(c.boundary, c.element, c.ex, c.ey, 0.0);
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  ContactSolver solver(mesh, scene);
  const bool shear = c.boundary != Boundary::symmetry;
  const Constraints con = build_constraints(mesh, scene, solver.intact());
  std::vector<int> I;
  for (int r = 0; r < con.n_rows(); ++r)
    if (is_interface(con.kind[r])) I.push_back(r);
  std::vector<Eigen::VectorXd> lambdas;
  std::vector<Eigen::Vector3d> strains, used;
  const std::vector<Eigen::Vector3d> sigmas = directions(6, shear, 11);
  Eigen::MatrixXd V(static_cast<Eigen::Index>(I.size()), 0);
  for (const Eigen::Vector3d& sigma : sigmas) {
    const Solution s = solver.solve(sigma, solver.intact());
    ASSERT_TRUE(s.converged());
    Eigen::VectorXd p(static_cast<Eigen::Index>(I.size()));
    for (std::size_t i = 0; i < I.size(); ++i) p(static_cast<Eigen::Index>(i)) = s.lambda(I[i]);
    if (p.cwiseAbs().maxCoeff() == 0) continue;  // every contact open: no column
    lambdas.push_back(s.lambda);
    strains.push_back(in_plane(engineering_from_tensor(s.strain), shear));
    used.push_back(sigma);
    V.conservativeResize(Eigen::NoChange, V.cols() + 1);
    V.col(V.cols() - 1) = p / p.cwiseAbs().maxCoeff();
  }
  const law::CondensedCell basis = condense_on_solutions(solver.setup(), lambdas);
  const law::CondensedCell expected = law::cell_on_basis(condense(solver.setup()), V);
  EXPECT_EQ(law::consistency_problem(basis), "");
  EXPECT_LE(basis.reciprocity_error, 1e-9);
  ASSERT_GE(basis.n_rows(), 3);
  ASSERT_EQ(basis.n_rows(), static_cast<int>(used.size()));
  EXPECT_LE((basis.S0 - expected.S0).norm(), 1e-10 * expected.S0.norm());
  EXPECT_LE((basis.Y - expected.Y).norm(), 1e-10 * expected.Y.norm());
  EXPECT_LE((basis.H - expected.H).norm(), 1e-10 * expected.H.norm());

  law::CellEvaluator law(basis);
  for (std::size_t j = 0; j < used.size(); ++j) {
    law::CellHistory h = law.unloaded();
    const law::CellResponse r = law.at_stress(used[j], h);
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_LE((in_plane(r.strain, shear) - strains[j]).norm(), against_solver * strains[j].norm()) << j;
  }
}

TEST(CondensedOnSolutions, RefusesAdhesionAndForeignMultipliers) {
  const Scene bonded = cell_scene(Boundary::periodic, Element::p2, 1, 1, 0.05);
  const mesh::Mesh mesh = mesh::build_mesh(bonded.geometry);
  ContactSolver solver(mesh, bonded);
  EXPECT_THROW(condense_on_solutions(solver.setup(), {}), InputError);
  const Scene contact = cell_scene(Boundary::periodic, Element::p2, 1, 1, 0.0);
  ContactSolver open(mesh, contact);
  EXPECT_THROW(condense_on_solutions(open.setup(), {Eigen::VectorXd::Ones(3)}), InputError);
  const Solution s = open.solve(Eigen::Vector3d(1, 1, 0), open.intact());  // all-round tension: every contact opens
  ASSERT_TRUE(s.converged());
  EXPECT_THROW(condense_on_solutions(open.setup(), {s.lambda}), InputError);  // no column
  const Solution c = open.solve(Eigen::Vector3d(-1, -1, 0), open.intact());
  ASSERT_TRUE(c.converged());
  EXPECT_EQ(condense_on_solutions(open.setup(), {s.lambda, c.lambda}).n_rows(), 1);
}

// The law does not depend on the unit of length: the same cell at sizes 1, 1e10 and 1e-10 (its
// fibre scaled with it; stresses, strains and the strengths, tractions in 2D, carry no length)
// gives the same strains for the same stresses, through the first breaks. The modes' rows of G, a rotation's carrying
// lengths and a translation's none, are scaled to unit length before the condensation splits them; unscaled, a cell of
// size 3e4 lost its law.
TEST(CondensedUnits, TheLawIsTheSameInAnyUnitOfLength) {
  std::vector<Eigen::Vector3d> strains;
  for (const double size : {1.0, 1e10, 1e-10}) {
    Scene scene = cell_scene(Boundary::periodic, Element::p2, 1, 1, 0.05);
    scene.geometry.cell_size = size;
    scene.geometry.fibre_radius = 0.3 * size;
    const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
    ContactSolver solver(mesh, scene);
    const law::CondensedCell cell = condense(solver.setup());
    ASSERT_EQ(law::consistency_problem(cell), "") << size;
    law::CellEvaluator law(cell);
    law::CellHistory h = law.unloaded();
    for (const double s : {0.02, 0.06, 0.1}) {
      const law::CellResponse r = law.at_stress(s * Eigen::Vector3d(1.0, 0.3, 0.2), h);
      ASSERT_TRUE(r.ok) << size << ": " << r.message;
      strains.push_back(r.strain);
    }
  }
  // The three sizes' strains agree to the round-off of the condensation (a few 1e-14 measured).
  for (std::size_t k = 3; k < strains.size(); ++k)
    EXPECT_LE((strains[k] - strains[k % 3]).norm(), 1e-10 * strains[k % 3].norm()) << k;
}

// With adhesion: the exact onset, then a path through the fuse with the bonds carried along it,
// against the full solver stepping the same path (sweep::LoadWalk); stress-driven, and
// strain-driven along the strains it reached.
TEST(CondensedAdhesion, ThroughTheFuseAlongAPathAsTheCellDoes) {
  for (const Element element : {Element::p1, Element::p2}) {
    Scene scene = cell_scene(Boundary::periodic, element, 1, 1, 0.05);
    // p2 off-centre, another material: no symmetry for the law to lean on.
    if (element == Element::p2) scene.geometry.fibre_offset = {0.08, -0.05}, scene.fibre = {70.0, 0.25};
    const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
    ContactSolver solver(mesh, scene);
    const law::CondensedCell cell = condense(solver.setup());
    EXPECT_EQ(law::consistency_problem(cell), "");
    EXPECT_LE(cell.reciprocity_error, 1e-9);
    ASSERT_TRUE(cell.adhesion());
    law::CellEvaluator law(cell);
    for (const Eigen::Vector3d& N : directions(3, true, 11)) {
      // The onset of §11 (a QP at tolerance 1e-10 on the lifted problem) against the law's.
      const double onset = solver.debond_onset(N);
      EXPECT_NEAR(law.onset(N), onset, against_solver * onset) << N.transpose();
      sweep::LoadWalk walk(solver, MacroState::stress(N), solver.intact());
      law::CellHistory h = law.unloaded();
      int broken_seen = 0;
      for (const double fraction : {0.5, 0.9, 1.05, 1.3, 1.8, 2.5}) {
        const double load = fraction * onset;
        const Solution s = walk.solve(load);
        ASSERT_TRUE(s.converged());
        walk.accept(load, s);
        law::CellHistory before = h;
        const law::CellResponse r = law.at_stress(load * N, h);
        ASSERT_TRUE(r.ok) << r.message;
        // The evaluator keeps the tangent of its last factorisation: a fresh one from the same
        // history gives the same tangent (no stale one across a change of the active set).
        law::CellEvaluator fresh(cell);
        const law::CellResponse again = fresh.at_stress(load * N, before);
        EXPECT_LE((again.tangent - r.tangent).norm(), 1e-10 * r.tangent.norm()) << fraction;
        const Eigen::Vector3d expected = engineering_from_tensor(s.strain);
        EXPECT_LE((r.strain - expected).norm(), against_solver * expected.norm())
            << to_string(element) << " at " << fraction << " × onset along " << N.transpose();
        const int broken = sweep::count_broken(solver.intact(), s.bonds);
        EXPECT_EQ(r.broken, broken) << fraction;
        if (fraction < 1) {
          EXPECT_EQ(r.broken, 0);
        }
        broken_seen = std::max(broken_seen, broken);
        // Strain-driven at the strain reached, from the same bond state: the same stress, no
        // new breaks. (From the state before the step it would differ past the onset: a
        // strain-driven step breaks at other stresses than a stress-driven one.)
        law::CellHistory same = h;
        const law::CellResponse back = law.at_strain(r.strain, same);
        ASSERT_TRUE(back.ok) << back.message;
        EXPECT_LE((back.stress - load * N).norm(), 1e-8 * load) << fraction;
        EXPECT_EQ(back.newly_broken, 0) << fraction;
      }
      EXPECT_GT(broken_seen, 0) << "the path must reach past the fuse";
    }
  }
}

// The bond rule (law/bond.hpp) is the one description of a row's bounds: the full solver's rows
// and the exact law's carry the same bounds for every pair in either state, and a broken pair
// has no tangential row on the solver's side.
TEST(BondRule, TheFullSolverAndTheExactLawGiveEachRowTheSameBounds) {
  Scene scene = cell_scene(Boundary::periodic, Element::p2, 1, 1, 0.05);
  scene.interface.tangential_strength = 0.03;
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  ContactSolver solver(mesh, scene);
  const law::CondensedCell cell = condense(solver.setup());
  const std::vector<double> length = interface_lengths(mesh);
  const double sn = scene.interface.normal_strength, st = scene.interface.tangential_strength;
  BondState some_broken = solver.intact();
  for (std::size_t p = 0; p < some_broken.size(); p += 3) some_broken[p] = 0;
  for (const BondState& bonds : {solver.intact(), some_broken}) {
    const Constraints con = build_constraints(mesh, scene, bonds);
    int i = 0;  // the cell's row of the intact state's row
    std::vector<int> tangential_rows(mesh.interface_pairs.size(), 0);
    for (int r = 0; r < con.n_rows(); ++r) {
      if (!is_interface(con.kind[r])) continue;
      const int p = con.pair[r];
      const auto kind = con.kind[r] == RowKind::tangential ? law::bond::Kind::tangential : law::bond::Kind::normal;
      const auto state = bonds[p] ? law::bond::State::intact : law::bond::State::broken;
      const law::bond::Bounds rule = law::bond::bounds(kind, state, sn, st, length[p]);
      // The rows store bounds / w: the product back is the rule to round-off.
      EXPECT_NEAR(con.lower(r) * con.weight(r), rule.lower, 1e-15 * sn) << r;
      EXPECT_EQ(std::isinf(con.upper(r)), std::isinf(rule.upper)) << r;
      if (!std::isinf(rule.upper)) {
        EXPECT_NEAR(con.upper(r) * con.weight(r), rule.upper, 1e-15 * st) << r;
      }
      tangential_rows[p] += kind == law::bond::Kind::tangential;
      if (bonds != solver.intact()) continue;
      // The exact law's rows are the intact state's, in its order.
      ASSERT_LT(i, cell.n_rows());
      EXPECT_EQ(cell.pair[i], p);
      EXPECT_EQ(cell.kind(i), kind);
      EXPECT_EQ(cell.bonded_bounds(i).lower, con.lower(r) * con.weight(r));
      const law::bond::Bounds broken = law::bond::bounds(kind, law::bond::State::broken, sn, st, length[p]);
      EXPECT_EQ(cell.broken_bounds(i).lower, broken.lower);
      EXPECT_EQ(cell.broken_bounds(i).upper, broken.upper);
      ++i;
    }
    if (bonds == solver.intact()) {
      EXPECT_EQ(i, cell.n_rows());
    }
    for (std::size_t p = 0; p < bonds.size(); ++p) EXPECT_EQ(tangential_rows[p], bonds[p] ? 1 : 0) << p;
  }
}

}  // namespace
}  // namespace dualcell::feti
