// A block of resolved cells with conditions per edge ([load] boundary = "edges"): bonded, it is
// the one-body primal solve with the same edges (an oracle that shares no constraint code);
// prescribed displacements and loads scale with the load factor; steps carry the bond history.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "feti/solver.hpp"
#include "mesh/mesh.hpp"
#include "primal/one_body.hpp"
#include "test_util.hpp"

namespace dualcell::feti {
namespace {

// A 4 × 1 block of cells (glass/epoxy-like contrast 20), every edge kind used across the cases.
Scene beam(const std::string& edges, double strength) {
  Scene s = parse_scene(testing::scene_text(4, 1, 2, 0.3, "[load]\nboundary = \"edges\"\n" + edges), "beam.toml");
  s.fibre = {20.0, 0.22};
  s.matrix = {1.0, 0.35};
  s.interface = {strength, strength};
  s.solver.tolerance = 1e-10;
  return s;
}

const std::string cantilever =
    "[edges.left]\ntype = \"fixed\"\n[edges.right]\ntype = \"traction\"\ntraction = [0, -0.01]\n"
    "[output]\nwatch = [4, 0]\n";
const std::string pulled =  // a prescribed end displacement, a roller, a point support
    "[edges.left]\ntype = \"roller\"\n[edges.right]\ntype = \"displacement\"\nux = 0.02\n"
    "[edges.top]\ntype = \"traction\"\ntraction = [0, -0.004]\ntraction_end = [0, 0.004]\n"
    "[[support]]\nat = [0, 0]\nfix = \"y\"\n[[point_load]]\nat = [2, 1]\nforce = [0, -0.003]\n";

// Bonded (strengths never reached): the dual solution is the one-body solve's, to 1e-8 (the QP
// stops at 1e-10 relative; cond(PFP) of these meshes ~1e2, as for the macro boundaries).
TEST(EdgesBoundary, BondedEqualsTheOneBodySolveWithTheSameEdges) {
  for (const std::string& edges : {cantilever, pulled}) {
    const Scene scene = beam(edges, 1e12);
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    ContactSolver solver(m, scene);
    for (double t : {1.0, -0.5}) {
      const Eigen::Vector3d p(t, 0, 0);
      const Solution s = solver.solve_fixed(p, solver.intact());
      ASSERT_TRUE(s.converged()) << s.qp.message << " " << s.primal_message;
      const Eigen::VectorXd u_ref = primal::solve_one_body(m, scene, solver.setup().load(p), false, true, nullptr, t);
      EXPECT_LT((s.u - u_ref).norm() / u_ref.norm(), 1e-8) << edges << " t " << t;
    }
  }
}

// Loads and prescribed displacements are one pattern times the factor: without adhesion
// (contact only, a cone) the response is positively homogeneous, u(2t) = 2 u(t), to the
// solver's tolerance; the prescribed ux = 0.02·t holds on every point of the right edge.
TEST(EdgesBoundary, LoadsAndPrescribedDisplacementsScaleWithTheFactor) {
  const Scene scene = beam(pulled, 0);
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  ContactSolver solver(m, scene);
  const Solution one = solver.solve(Eigen::Vector3d(0.5, 0, 0), solver.intact());
  const Solution two = solver.solve(Eigen::Vector3d(1.0, 0, 0), solver.intact());
  ASSERT_TRUE(one.converged() && two.converged());
  EXPECT_LT((two.u - 2 * one.u).norm() / two.u.norm(), 1e-8);
  // The residual of the rows B u = t·c is the dual gradient, which the QP drives below its
  // relative tolerance: the prescribed value holds to 10·tolerance·‖u‖∞ (measured 1.1e-12,
  // i.e. 4e-11 of ‖u‖∞; the copies of a point follow the held one through glue rows).
  const double bound = 10 * scene.solver.tolerance * two.u.lpNorm<Eigen::Infinity>();
  for (const mesh::Edge& e : m.boundary_edges[mesh::right])
    for (int v : {e.a, e.b}) EXPECT_NEAR(two.u(2 * v), 0.02, bound);
  EXPECT_THROW(solver.solve(Eigen::Vector3d(1, 1, 0), solver.intact()), InputError);
}

// With adhesion the first break comes at the exact onset t* (one solve): just below it nothing
// breaks, just above it something does, and a later step at a lower load keeps the breaks.
TEST(EdgesBoundary, FirstBreakAtTheExactOnsetAndBreaksAreKept) {
  const Scene scene = beam(cantilever, 0.02);
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  ContactSolver solver(m, scene);
  const double onset = solver.debond_onset(Eigen::Vector3d(1, 0, 0));
  ASSERT_TRUE(std::isfinite(onset) && onset > 0);
  const Solution below = solver.solve(Eigen::Vector3d(onset * (1 - 1e-6), 0, 0), solver.intact());
  ASSERT_TRUE(below.converged());
  EXPECT_EQ(below.newly_broken, 0);
  const Solution above = solver.solve(Eigen::Vector3d(onset * 1.5, 0, 0), solver.intact());
  ASSERT_TRUE(above.converged());
  EXPECT_GT(above.newly_broken, 0);
  const Solution back = solver.solve(Eigen::Vector3d(onset * 0.5, 0, 0), above.bonds);
  ASSERT_TRUE(back.converged());
  EXPECT_EQ(back.bonds, above.bonds);
}

}  // namespace
}  // namespace dualcell::feti
