// The plane-strain triangle and subdomain assembly: symmetry, definiteness, rigid modes, the
// patch test and consistent loads.
#include "fem/element.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <map>
#include <random>

#include "fem/assembly.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::fem {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

TEST(Element, PlaneStrainDMatchesTheFormula) {
  const Eigen::Matrix3d D = plane_strain_D({2.0, 0.25});
  // λ = Eν/((1+ν)(1-2ν)) = 0.8, μ = E/(2(1+ν)) = 0.8: D = [[λ+2μ, λ, 0], [λ, λ+2μ, 0], [0, 0, μ]].
  EXPECT_NEAR(D(0, 0), 2.4, 1e-15);
  EXPECT_NEAR(D(0, 1), 0.8, 1e-15);
  EXPECT_NEAR(D(2, 2), 0.8, 1e-15);
  EXPECT_EQ(D(0, 2), 0);
}

TEST(Element, StiffnessIsSymmetricSemiDefiniteWithRigidKernel) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Vector2d p[3];
    for (auto& q : p) q = {coord(rng), coord(rng)};
    double area;
    strain_displacement(p[0], p[1], p[2], area);
    if (std::abs(area) < 0.05) continue;
    const Matrix66 K = triangle_stiffness(p[0], p[1], p[2], plane_strain_D({3.0, 0.3}));
    const double scale = K.norm();
    EXPECT_LE((K - K.transpose()).norm(), 10 * eps * scale);
    Eigen::SelfAdjointEigenSolver<Matrix66> eig(K);
    const auto lambda = eig.eigenvalues();
    // Exactly three zero eigenvalues (to round-off, 1e3·eps·‖K‖), three positive.
    int zeros = 0;
    for (int i = 0; i < 6; ++i) {
      EXPECT_GT(lambda(i), -1e3 * eps * scale);
      zeros += std::abs(lambda(i)) < 1e3 * eps * scale;
    }
    EXPECT_EQ(zeros, 3);
    // Rigid modes: translations and the rotation (-y, x).
    Vector6 tx, ty, rot;
    for (int v = 0; v < 3; ++v) {
      tx.segment<2>(2 * v) << 1, 0;
      ty.segment<2>(2 * v) << 0, 1;
      rot.segment<2>(2 * v) << -p[v].y(), p[v].x();
    }
    for (const Vector6& mode : {tx, ty, rot}) EXPECT_LE((K * mode).norm(), 100 * eps * scale * mode.norm());
  }
}

mesh::Mesh irregular_mesh() {
  Geometry g;
  g.cells = {1, 1};
  g.fibre_radius = 0.27;
  g.fibre_offset = {0.08, -0.05};
  g.degree = 2;
  return mesh::build_mesh(g);
}

// Edges of subdomain s that belong to one triangle only: its boundary, counter-clockwise.
std::vector<std::array<int, 2>> subdomain_boundary(const mesh::Mesh& m, int s) {
  std::map<std::pair<int, int>, int> count;
  const auto& sub = m.subdomains[s];
  for (int t = sub.triangle_begin; t < sub.triangle_end; ++t)
    for (int e = 0; e < 3; ++e) {
      const int a = m.triangles[t][e], b = m.triangles[t][(e + 1) % 3];
      count[{std::min(a, b), std::max(a, b)}]++;
    }
  std::vector<std::array<int, 2>> edges;
  for (int t = sub.triangle_begin; t < sub.triangle_end; ++t)
    for (int e = 0; e < 3; ++e) {
      const int a = m.triangles[t][e], b = m.triangles[t][(e + 1) % 3];
      if (count[{std::min(a, b), std::max(a, b)}] == 1) edges.push_back({a, b});
    }
  return edges;
}

TEST(Assembly, PatchTestLinearFieldGivesConstantStressAndConsistentForces) {
  const mesh::Mesh m = irregular_mesh();
  const Material material{5.0, 0.3};
  const Eigen::Matrix3d D = plane_strain_D(material);
  // u = A x + b with a general (non-symmetric) A: strain sym(A), stress D ε.
  Eigen::Matrix2d A;
  A << 1e-3, 4e-4, -2e-4, -7e-4;
  const Eigen::Vector2d b(0.3, -0.1);
  const Eigen::Vector3d strain(A(0, 0), A(1, 1), A(0, 1) + A(1, 0));
  const Eigen::Vector3d sigma = D * strain;
  Eigen::Matrix2d sigma_tensor;
  sigma_tensor << sigma(0), sigma(2), sigma(2), sigma(1);
  for (int s = 0; s < 2; ++s) {
    const auto& sub = m.subdomains[s];
    Eigen::VectorXd u(2 * sub.n_nodes());
    for (int v = 0; v < sub.n_nodes(); ++v) u.segment<2>(2 * v) = A * m.nodes[sub.node_begin + v] + b;
    Eigen::VectorXd u_global = Eigen::VectorXd::Zero(m.dim_u());
    u_global.segment(2 * sub.node_begin, u.size()) = u;
    const Eigen::MatrixXd stress = element_stresses(m, material, material, u_global);
    // Round-off: the strain is a difference of displacements of size |u| ≈ 0.3 over edges of
    // h ≥ h_min, so its error is a few eps·|u|/h_min, amplified by ‖D‖.
    double h_min = 1;
    for (int t = sub.triangle_begin; t < sub.triangle_end; ++t)
      for (int e = 0; e < 3; ++e)
        h_min = std::min(h_min, (m.nodes[m.triangles[t][e]] - m.nodes[m.triangles[t][(e + 1) % 3]]).norm());
    const double tolerance = 64 * eps * u.cwiseAbs().maxCoeff() / h_min * D.norm();
    for (int t = sub.triangle_begin; t < sub.triangle_end; ++t)
      EXPECT_LE((stress.row(t).transpose() - sigma).norm(), tolerance) << "triangle " << t;
    // K u equals the consistent nodal forces of the traction σ·n on the subdomain boundary.
    const Eigen::SparseMatrix<double> K = assemble_stiffness(m, s, material);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(m.dim_u());
    for (const auto& [a, bn] : subdomain_boundary(m, s)) {
      const Eigen::Vector2d e = m.nodes[bn] - m.nodes[a];
      const Eigen::Vector2d normal = Eigen::Vector2d(e.y(), -e.x()).normalized();
      const Eigen::Vector2d t = sigma_tensor * normal;
      add_edge_traction(m, a, bn, t, t, f);
    }
    const Eigen::VectorXd Ku = K * u;
    const Eigen::VectorXd f_sub = f.segment(2 * sub.node_begin, u.size());
    // Interior nodes: exact equilibrium (forces cancel); boundary nodes: the consistent load.
    EXPECT_LE((Ku - f_sub).norm(), 1e-11 * f_sub.norm()) << "subdomain " << s;
  }
}

TEST(Assembly, SubdomainKernelIsTheRigidModesAndRankIsDimMinusThree) {
  for (int k : {1, 2}) {
    Geometry g;
    g.cells = {2, 1};
    g.fibre_radius = 0.35;
    g.degree = k;
    const mesh::Mesh m = mesh::build_mesh(g);
    for (int s = 0; s < static_cast<int>(m.subdomains.size()); ++s) {
      const Eigen::SparseMatrix<double> K = assemble_stiffness(m, s, {1e3, 0.3});
      const Eigen::MatrixXd R = rigid_body_modes(m, s);
      const double scale = Eigen::MatrixXd(K).norm();
      EXPECT_LE((K * R).norm(), 1e3 * eps * scale) << "K_i R_i = 0 to round-off, subdomain " << s;
      EXPECT_LE((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(K), Eigen::EigenvaluesOnly);
      const double largest = eig.eigenvalues().maxCoeff();
      int zeros = 0;
      for (int i = 0; i < eig.eigenvalues().size(); ++i) zeros += eig.eigenvalues()(i) < 1e-10 * largest;
      EXPECT_EQ(zeros, 3) << "rank = dim - 3, subdomain " << s << ", degree " << k;
    }
  }
}

TEST(Assembly, ConsistentLoadsIntegrateExactly) {
  const mesh::Mesh m = irregular_mesh();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(m.dim_u());
  add_body_force(m, 0, {2.0, -1.0}, f);
  add_body_force(m, 1, {2.0, -1.0}, f);
  Eigen::Vector2d total = Eigen::Vector2d::Zero();
  for (int v = 0; v < m.n_nodes(); ++v) total += f.segment<2>(2 * v);
  EXPECT_NEAR(total.x(), 2.0, 1e-13);  // body force × block area 1
  EXPECT_NEAR(total.y(), -1.0, 1e-13);
  // A linearly varying traction t(s) on one edge: total force L (t_a + t_b)/2, moment exact.
  Eigen::VectorXd g = Eigen::VectorXd::Zero(m.dim_u());
  const auto [a, b] = m.boundary_edges[mesh::bottom][0];
  add_edge_traction(m, a, b, {1, 0}, {3, 0}, g);
  const double L = (m.nodes[b] - m.nodes[a]).norm();
  EXPECT_NEAR(g(2 * a) + g(2 * b), 2 * L, 1e-15);
  EXPECT_NEAR(g(2 * a), L * 5 / 6, 1e-15);
}

}  // namespace
}  // namespace dualcell::fem
