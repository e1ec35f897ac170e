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

TEST(Element, QuadraticStiffnessOfACurvedElementIsSymmetricSemiDefiniteWithRigidKernel) {
  // A 6-node triangle with its mid-side nodes pushed off the chords (a curved element, as on
  // the rim): the isoparametric map still reproduces rigid motions exactly, so K has exactly
  // three zero eigenvalues and nine positive ones.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> shift(-0.05, 0.05);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Eigen::Vector2d> x = {{0, 0}, {1, 0.1}, {0.3, 0.9}};
    for (int e = 0; e < 3; ++e) x.push_back((x[e] + x[(e + 1) % 3]) / 2 + Eigen::Vector2d(shift(rng), shift(rng)));
    const Eigen::MatrixXd K = element_stiffness(x, plane_strain_D({3.0, 0.3}));
    const double scale = K.norm();
    EXPECT_LE((K - K.transpose()).norm(), 10 * eps * scale);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K);
    int zeros = 0;
    for (int i = 0; i < 12; ++i) {
      EXPECT_GT(eig.eigenvalues()(i), -1e3 * eps * scale);
      zeros += std::abs(eig.eigenvalues()(i)) < 1e3 * eps * scale;
    }
    EXPECT_EQ(zeros, 3);
    Eigen::VectorXd rot(12);
    for (int v = 0; v < 6; ++v) rot.segment<2>(2 * v) << -x[v].y(), x[v].x();
    EXPECT_LE((K * rot).norm(), 100 * eps * scale * rot.norm());
  }
}

TEST(Element, QuadratureRulesAreExactToTheirDegree) {
  // Triangle rule: ∫ L₁^i L₂^j over the reference triangle = i! j! / (i + j + 2)! for i + j ≤ 4.
  const auto factorial = [](int n) { return std::tgamma(n + 1.0); };
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; i + j <= 4; ++j) {
      double sum = 0;
      for (const TrianglePoint& q : triangle_rule()) sum += q.weight * std::pow(q.L1, i) * std::pow(q.L2, j);
      EXPECT_NEAR(sum, factorial(i) * factorial(j) / factorial(i + j + 2), 1e-16) << i << " " << j;
    }
  // Edge rule: ∫₀¹ s^i ds = 1/(i + 1) for i ≤ 9.
  for (int i = 0; i <= 9; ++i) {
    double sum = 0;
    for (const EdgePoint& q : edge_rule()) sum += q.weight * std::pow(q.s, i);
    EXPECT_NEAR(sum, 1.0 / (i + 1), 1e-16) << i;
  }
}

mesh::Mesh irregular_mesh(Element element = Element::p1) {
  Geometry g;
  g.cells = {1, 1};
  g.fibre_radius = 0.27;
  g.fibre_offset = {0.08, -0.05};
  g.degree = 2;
  g.element = element;
  return mesh::build_mesh(g);
}

// Edges of subdomain s that belong to one triangle only: its boundary, counter-clockwise, as
// (a, b, mid) with mid = −1 for p1.
std::vector<mesh::Edge> subdomain_boundary(const mesh::Mesh& m, int s) {
  std::map<std::pair<int, int>, int> count;
  const auto& sub = m.subdomains[s];
  for (int t = sub.triangle_begin; t < sub.triangle_end; ++t)
    for (int e = 0; e < 3; ++e) {
      const int a = m.triangles[t][e], b = m.triangles[t][(e + 1) % 3];
      count[{std::min(a, b), std::max(a, b)}]++;
    }
  std::vector<mesh::Edge> edges;
  for (int t = sub.triangle_begin; t < sub.triangle_end; ++t)
    for (int e = 0; e < 3; ++e) {
      const int a = m.triangles[t][e], b = m.triangles[t][(e + 1) % 3];
      if (count[{std::min(a, b), std::max(a, b)}] == 1)
        edges.push_back({a, b, m.triangles.width() == 6 ? m.triangles[t][3 + e] : -1});
    }
  return edges;
}

// ∫ φ_i σ·n ds over a (possibly curved) edge, n ds = (y', −x') ds: the consistent nodal forces
// of a constant stress.
void add_stress_traction(const mesh::Mesh& m, const mesh::Edge& edge, const Eigen::Matrix2d& sigma,
                         Eigen::VectorXd& f) {
  const int v[3] = {edge.a, edge.b, edge.mid}, n = edge.mid >= 0 ? 3 : 2;
  for (const EdgePoint& q : edge_rule()) {
    double phi[3], dphi[3];
    edge_shape(n, q.s, phi, dphi);
    Eigen::Vector2d dx = Eigen::Vector2d::Zero();
    for (int i = 0; i < n; ++i) dx += dphi[i] * m.nodes[v[i]];
    for (int i = 0; i < n; ++i)
      f.segment<2>(2 * v[i]) += q.weight * phi[i] * (sigma * Eigen::Vector2d(dx.y(), -dx.x()));
  }
}

class Assembly : public ::testing::TestWithParam<Element> {};
INSTANTIATE_TEST_SUITE_P(Order, Assembly, ::testing::Values(Element::p1, Element::p2),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST_P(Assembly, PatchTestLinearFieldGivesConstantStressAndConsistentForces) {
  // Both orders reproduce linear fields exactly (isoparametric p2 included, curved rim edges
  // too), so a linear u gives the exact constant stress and K u equals the consistent forces of
  // σ·n on the subdomain boundary.
  const mesh::Mesh m = irregular_mesh(GetParam());
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
    const ElementStresses stress = element_stresses(m, material, material, u_global);
    // Round-off: the strain is a difference of displacements of size |u| ≈ 0.3 over edges of
    // h ≥ h_min, so its error is a few eps·|u|/h_min, amplified by ‖D‖.
    double h_min = 1;
    for (int t = sub.triangle_begin; t < sub.triangle_end; ++t)
      for (int e = 0; e < 3; ++e)
        h_min = std::min(h_min, (m.nodes[m.triangles[t][e]] - m.nodes[m.triangles[t][(e + 1) % 3]]).norm());
    const double tolerance = 64 * eps * u.cwiseAbs().maxCoeff() / h_min * D.norm();
    for (int t = sub.triangle_begin; t < sub.triangle_end; ++t) {
      EXPECT_LE((stress.centroid.row(t).transpose() - sigma).norm(), tolerance) << "triangle " << t;
      EXPECT_LE((stress.average.row(t).transpose() - sigma).norm(), tolerance) << "triangle " << t;
    }
    // K u equals the consistent nodal forces of the traction σ·n on the subdomain boundary.
    const Eigen::SparseMatrix<double> K = assemble_stiffness(m, s, material);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(m.dim_u());
    for (const mesh::Edge& edge : subdomain_boundary(m, s)) add_stress_traction(m, edge, sigma_tensor, f);
    const Eigen::VectorXd Ku = K * u;
    const Eigen::VectorXd f_sub = f.segment(2 * sub.node_begin, u.size());
    // Interior nodes: exact equilibrium (forces cancel); boundary nodes: the consistent load.
    EXPECT_LE((Ku - f_sub).norm(), 1e-11 * f_sub.norm()) << "subdomain " << s;
  }
}

TEST_P(Assembly, SubdomainKernelIsTheRigidModesAndRankIsDimMinusThree) {
  for (int k : {1, 2}) {
    Geometry g;
    g.cells = {2, 1};
    g.fibre_radius = 0.35;
    g.degree = k;
    g.element = GetParam();
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

TEST_P(Assembly, ConsistentLoadsIntegrateExactly) {
  const mesh::Mesh m = irregular_mesh(GetParam());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(m.dim_u());
  add_body_force(m, 0, {2.0, -1.0}, f);
  add_body_force(m, 1, {2.0, -1.0}, f);
  Eigen::Vector2d total = Eigen::Vector2d::Zero();
  for (int v = 0; v < m.n_nodes(); ++v) total += f.segment<2>(2 * v);
  EXPECT_NEAR(total.x(), 2.0, 1e-13);  // body force × block area 1
  EXPECT_NEAR(total.y(), -1.0, 1e-13);
  // A linearly varying traction t(s) on one edge: total force L (t_a + t_b)/2, moment exact.
  Eigen::VectorXd g = Eigen::VectorXd::Zero(m.dim_u());
  const mesh::Edge edge = m.boundary_edges[mesh::bottom][0];
  const auto [a, b, mid] = edge;
  add_edge_traction(m, edge, {1, 0}, {3, 0}, g);
  const double L = (m.nodes[b] - m.nodes[a]).norm();
  const double f_mid = mid >= 0 ? g(2 * mid) : 0;
  EXPECT_NEAR(g(2 * a) + g(2 * b) + f_mid, 2 * L, 1e-15);
  // ∫ φ_a t ds with t = 1 + 2s: L·5/6 for the linear φ_a = 1 − s; for the quadratic
  // φ_a = (1 − s)(1 − 2s) it is L/6, and ∫ 4s(1 − s)(1 + 2s) ds = 4/3 gives 4L/3 at the middle.
  if (mid < 0) {
    EXPECT_NEAR(g(2 * a), L * 5 / 6, 1e-15);
  } else {
    EXPECT_NEAR(g(2 * a), L / 6, 1e-15);
    EXPECT_NEAR(g(2 * mid), L * 4 / 3, 1e-15);
  }
}

TEST(Assembly, InterfaceEdgeWeightsAreSimpsonOnAStraightEdgeAndTheArcOnACircle) {
  // A straight 3-node edge with its middle node at the midpoint: ∫ φ ds = L/6, L/6, 4L/6.
  const std::vector<Eigen::Vector2d> straight = {{0, 0}, {2, 0}, {1, 0}};
  const auto w = edge_weights(straight);
  EXPECT_NEAR(w[0], 2.0 / 6, 1e-15);
  EXPECT_NEAR(w[1], 2.0 / 6, 1e-15);
  EXPECT_NEAR(w[2], 8.0 / 6, 1e-15);
  // Three points on a circle of radius r over an angle θ: the weights sum to the length of the
  // parabola through them, which misses the arc r θ by O(θ⁵) (relative θ⁴; the chord's miss is
  // O(θ³)): ratio 32 per halving.
  const double r = 0.3;
  double previous = 0;
  for (double theta : {0.4, 0.2, 0.1}) {
    const std::vector<Eigen::Vector2d> arc = {
        {r, 0}, {r * std::cos(theta), r * std::sin(theta)}, {r * std::cos(theta / 2), r * std::sin(theta / 2)}};
    const auto v = edge_weights(arc);
    const double error = std::abs(v[0] + v[1] + v[2] - r * theta);
    if (previous > 0) {
      EXPECT_NEAR(previous / error, 32, 1) << "theta " << theta;
    }
    previous = error;
  }
}

}  // namespace
}  // namespace dualcell::fem
