#include "primal/antiplane.hpp"

#include <Eigen/SparseCore>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "core/union_find.hpp"
#include "fem/element.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace dualcell::primal {

namespace {

// Every quadrature point of every triangle: point(tri, w, ∇φ) with w its weight times |det J|
// times the phase's μ, and ∇φ (2 × nodes) the shape functions' gradients (rows 0 and 1 of B at
// each node's x and y columns).
template <class Point>
void for_each_point(const mesh::Mesh& mesh, double mu_fibre, double mu_matrix, Point&& point) {
  const int nodes = mesh.triangles.width();
  Eigen::Matrix2Xd grad_phi(2, nodes);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto tri = mesh.triangles[t];
    const double mu = mesh.subdomains[mesh.triangle_subdomain[t]].is_fibre ? mu_fibre : mu_matrix;
    const std::vector<Eigen::Vector2d> x = mesh::triangle_points(mesh, static_cast<int>(t));
    for (const fem::TrianglePoint& q : fem::triangle_rule()) {
      double det_J;
      const Eigen::MatrixXd B = fem::strain_displacement_at(x, q.L1, q.L2, det_J);
      for (int i = 0; i < nodes; ++i) grad_phi.col(i) = Eigen::Vector2d(B(0, 2 * i), B(1, 2 * i + 1));
      point(tri, q.weight * std::abs(det_J) * mu, grad_phi);
    }
  }
}

// The antiplane problem's body for a bond state: the mesh's points merged with their periodic
// partners and, where bonded, their interface partners; one unknown per body point; one held
// unknown per piece (w̃ = 0 there: w̃ is defined up to a constant on each piece, so holding one
// value gives a generalised inverse K⁺, exact on every load that sums to 0 on each piece); K
// factorised by CHOLMOD.
class Body {
 public:
  Body(const mesh::Mesh& mesh, double mu_fibre, double mu_matrix, const std::vector<char>& bonded)
      : mesh_(mesh), points_(mesh.n_points()) {
    for (const mesh::PeriodicPair& pair : mesh.periodic_pairs) points_.join(pair.point, pair.partner);
    for (std::size_t p = 0; p < mesh.interface_pairs.size(); ++p)
      if (!bonded.empty() && bonded[p]) {
        const auto [f, m] = mesh.interface_pairs[p];
        points_.join(mesh.point_of[f], mesh.point_of[m]);
      }
    unknown_.assign(mesh.n_points(), -1);
    int n = 0;
    for (int q = 0; q < mesh.n_points(); ++q)
      if (points_.find(q) == q) unknown_[q] = n++;
    UnionFind pieces(n);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int i = 1; i < mesh.triangles.width(); ++i)
        pieces.join(dof(mesh.triangles[t][0]), dof(mesh.triangles[t][i]));
    piece_.resize(n);
    free_.assign(n, -1);
    for (int d = 0; d < n; ++d) piece_[d] = pieces.find(d);
    for (int d = 0; d < n; ++d)
      if (piece_[d] != d) free_[d] = n_free_++;
    std::vector<Eigen::Triplet<double>> entries;
    f_ = Eigen::MatrixXd::Zero(n_free_, 2);  // −∫ μ ∇φ·Γ dA for Γ = e_x, e_y
    const int nodes = mesh.triangles.width();
    for_each_point(mesh, mu_fibre, mu_matrix, [&](const auto& tri, double w, const Eigen::Matrix2Xd& grad_phi) {
      for (int i = 0; i < nodes; ++i) {
        const int a = free_[dof(tri[i])];
        if (a < 0) continue;
        f_.row(a) -= w * grad_phi.col(i).transpose();
        for (int j = 0; j < nodes; ++j)
          if (const int b = free_[dof(tri[j])]; b >= 0)
            entries.emplace_back(a, b, w * grad_phi.col(i).dot(grad_phi.col(j)));
      }
    });
    Eigen::SparseMatrix<double> K(n_free_, n_free_);
    K.setFromTriplets(entries.begin(), entries.end());
    if (const linalg::CholeskyStatus status = cholesky_.compute(K); status != linalg::CholeskyStatus::ok)
      throw std::runtime_error("longitudinal_shear: the factorisation failed: " +
                               std::string(linalg::to_string(status)));
  }

  // The body's unknown of a mesh node (held ones included) and its piece.
  int dof(int node) { return unknown_[points_.find(mesh_.point_of[node])]; }
  int piece(int node) { return piece_[dof(node)]; }
  // The unit shears' loads (n_free × 2).
  const Eigen::MatrixXd& f() const { return f_; }
  int n_free() const { return n_free_; }
  // The free unknown of a mesh node, −1 where held.
  int free(int node) { return free_[dof(node)]; }

  // w̃ = K⁺ b per mesh node (0 at the held ones).
  Eigen::VectorXd solve(const Eigen::VectorXd& b) {
    cholesky_.solve(b, z_);
    Eigen::VectorXd w(mesh_.n_nodes());
    for (int v = 0; v < mesh_.n_nodes(); ++v) {
      const int a = free(v);
      w(v) = a < 0 ? 0.0 : z_(a);
    }
    return w;
  }

 private:
  const mesh::Mesh& mesh_;
  UnionFind points_;
  std::vector<int> unknown_, piece_, free_;
  int n_free_ = 0;
  Eigen::MatrixXd f_;
  linalg::SparseCholesky cholesky_;
  Eigen::VectorXd z_;
};

// G_cd = (1/|Ω|) Σ ∫ μ (e_c + ∇w̃_c)·(e_d + ∇w̃_d) dA for w̃ (nodes × 2) of the unit shears: the
// energy form, symmetric by construction; at the discrete solution it is ⟨τ⟩ of unit shear d
// along c (∫ μ ∇φ·(e_d + ∇w̃_d) vanishes on every unknown: the Galerkin equations). Averaged
// with its transpose: symmetric to the last bit, not only to round-off.
Eigen::Matrix2d energy_modulus(const mesh::Mesh& mesh, double mu_fibre, double mu_matrix,
                               const Eigen::MatrixXd& w_tilde) {
  Eigen::Matrix2d G = Eigen::Matrix2d::Zero();
  const int nodes = mesh.triangles.width();
  for_each_point(mesh, mu_fibre, mu_matrix, [&](const auto& tri, double w, const Eigen::Matrix2Xd& grad_phi) {
    Eigen::Matrix2d grad = Eigen::Matrix2d::Identity();  // column c: Γ + ∇w̃ of unit shear c
    for (int i = 0; i < nodes; ++i) grad += grad_phi.col(i) * w_tilde.row(tri[i]);
    G += w * grad.transpose() * grad;
  });
  return (G + G.transpose()).eval() / (2 * mesh.block_width() * mesh.block_height());
}

// w̃ of the unit shears Γ = e_x, e_y per node (columns).
Eigen::MatrixXd unit_shears(Body& body, int n_nodes) {
  Eigen::MatrixXd w(n_nodes, 2);
  for (int c = 0; c < 2; ++c) w.col(c) = body.solve(body.f().col(c));
  return w;
}

}  // namespace

LongitudinalShear longitudinal_shear(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                     const std::vector<char>& bonded) {
  if (!bonded.empty() && bonded.size() != mesh.interface_pairs.size())
    throw std::invalid_argument("longitudinal_shear: " + std::to_string(bonded.size()) + " bond states for " +
                                std::to_string(mesh.interface_pairs.size()) + " interface pairs");
  const double mu_fibre = fem::phase_stiffness(fibre).G_L, mu_matrix = fem::phase_stiffness(matrix).G_L;
  Body body(mesh, mu_fibre, mu_matrix, bonded.empty() ? std::vector<char>(mesh.interface_pairs.size(), 1) : bonded);
  LongitudinalShear out;
  out.w_tilde = unit_shears(body, mesh.n_nodes());
  out.G = energy_modulus(mesh, mu_fibre, mu_matrix, out.w_tilde);
  return out;
}

namespace {

// One solve of the antiplane body at Γ: the pairs `tied` tied, the pairs `slipping` (±1) free to
// jump with the force ±strength across them; ⟨τ⟩, every pair's force along z (a tied pair's the
// tie's, a slipping pair's its strength, 0 otherwise) and every pair's jump.
struct TiedSolve {
  ShearResponse response;
  Eigen::VectorXd jump;
};
// Per node, the place its fibre force adds to: the periodic class of its point for a fibre node
// (a fibre cut by the block's edges meets its matrix at both images of a place), −1 otherwise.
std::vector<int> fibre_places(const mesh::Mesh& mesh) {
  UnionFind place(mesh.n_points());
  for (const mesh::PeriodicPair& pair : mesh.periodic_pairs) place.join(pair.point, pair.partner);
  const std::vector<char> on_fibre = mesh::fibre_nodes(mesh);
  std::vector<int> out(mesh.n_nodes(), -1);
  for (int v = 0; v < mesh.n_nodes(); ++v)
    if (on_fibre[v]) out[v] = place.find(mesh.point_of[v]);
  return out;
}

TiedSolve tied_solve(const mesh::Mesh& mesh, double mu_fibre, double mu_matrix, const std::vector<int>& places,
                     const std::vector<char>& tied, const std::vector<signed char>& slipping,
                     const std::vector<double>& strength, const Eigen::Vector2d& gamma) {
  const std::size_t P = tied.size();
  Body body(mesh, mu_fibre, mu_matrix, tied);
  // K w̃ = f Γ − Jᵀq: the slipping pairs' forces q on their nodes, + on the fibre's, − on the matrix's.
  Eigen::VectorXd b = body.f() * gamma;
  for (std::size_t p = 0; p < P; ++p)
    if (slipping[p]) {
      const double q = slipping[p] * strength[p];
      if (const int a = body.free(mesh.interface_pairs[p][0]); a >= 0) b(a) -= q;
      if (const int a = body.free(mesh.interface_pairs[p][1]); a >= 0) b(a) += q;
    }
  const Eigen::VectorXd w = body.solve(b);
  // Per node, the internal force of the elements that hold it, ∫ μ ∇φ·(Γ + ∇w̃) dA, and ⟨τ⟩.
  Eigen::VectorXd internal = Eigen::VectorXd::Zero(mesh.n_nodes());
  TiedSolve out;
  const int nodes = mesh.triangles.width();
  for_each_point(mesh, mu_fibre, mu_matrix, [&](const auto& tri, double weight, const Eigen::Matrix2Xd& grad_phi) {
    Eigen::Vector2d grad = gamma;
    for (int i = 0; i < nodes; ++i) grad += grad_phi.col(i) * w(tri[i]);
    out.response.tau += weight * grad;
    for (int i = 0; i < nodes; ++i) internal(tri[i]) += weight * grad_phi.col(i).dot(grad);
  });
  out.response.tau /= mesh.block_width() * mesh.block_height();
  // A tied pair's tie carries what the fibre's elements at its place do not balance themselves:
  // the internal forces of the fibre's nodes there, summed over the place's periodic images.
  Eigen::VectorXd fibre_force = Eigen::VectorXd::Zero(mesh.n_points());
  for (int v = 0; v < mesh.n_nodes(); ++v)
    if (places[v] >= 0) fibre_force(places[v]) += internal(v);
  out.response.pair_forces = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(P));
  out.jump = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(P));
  for (std::size_t p = 0; p < P; ++p) {
    const auto [f, m] = mesh.interface_pairs[p];
    const auto i = static_cast<Eigen::Index>(p);
    if (tied[p]) out.response.pair_forces(i) = -fibre_force(places[f]);
    if (slipping[p]) out.response.pair_forces(i) = slipping[p] * strength[p];
    out.jump(i) = w(f) - w(m);
  }
  return out;
}

}  // namespace

ShearResponse longitudinal_shear_at(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                    const std::vector<char>& bonded, const Eigen::Vector2d& gamma,
                                    const std::vector<double>& strength) {
  const std::size_t P = mesh.interface_pairs.size();
  if (bonded.size() != P || (!strength.empty() && strength.size() != P))
    throw std::invalid_argument("longitudinal_shear_at: " + std::to_string(bonded.size()) + " bond states and " +
                                std::to_string(strength.size()) + " strengths for " + std::to_string(P) +
                                " interface pairs");
  const double mu_fibre = fem::phase_stiffness(fibre).G_L, mu_matrix = fem::phase_stiffness(matrix).G_L;
  // The active set of the ties' bounds |q| ≤ strength, one change at a time: a slipping pair
  // whose jump opposes its force is tied again (the worst first), else the tie furthest past its
  // strength slips. Each step is one linear solve; with no strengths, the first is the answer.
  const std::vector<int> places = fibre_places(mesh);
  std::vector<signed char> slipping(P, 0);
  std::vector<char> tied(P);
  for (std::size_t step = 0; step <= 4 * P + 8; ++step) {
    for (std::size_t p = 0; p < P; ++p) tied[p] = bonded[p] && !slipping[p];
    const TiedSolve s = tied_solve(mesh, mu_fibre, mu_matrix, places, tied, slipping, strength, gamma);
    if (strength.empty()) return s.response;
    // Round-off decides neither change: a jump against its force of less than 1e-12 of the
    // largest jump, or a force past its strength by less than 1e-12 of it, is none (without this
    // margin a tie at its strength to the last digit slips and ties again for ever).
    const double jump_floor = 1e-12 * s.jump.cwiseAbs().maxCoeff();
    std::size_t worst = P;
    double worst_amount = jump_floor;
    for (std::size_t p = 0; p < P; ++p)
      if (slipping[p] && slipping[p] * s.jump(static_cast<Eigen::Index>(p)) < -worst_amount)
        worst = p, worst_amount = -slipping[p] * s.jump(static_cast<Eigen::Index>(p));
    if (worst < P) {
      slipping[worst] = 0;
      continue;
    }
    worst_amount = 0;
    for (std::size_t p = 0; p < P; ++p) {
      const double past = std::abs(s.response.pair_forces(static_cast<Eigen::Index>(p))) - strength[p];
      if (tied[p] && past > 1e-12 * strength[p] && past > worst_amount) worst = p, worst_amount = past;
    }
    if (worst == P) return s.response;
    slipping[worst] = s.response.pair_forces(static_cast<Eigen::Index>(worst)) > 0 ? 1 : -1;
  }
  throw std::runtime_error("longitudinal_shear_at: the ties' active set did not settle");
}

CondensedShear condense_longitudinal_shear(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                           bool rows) {
  const double mu_fibre = fem::phase_stiffness(fibre).G_L, mu_matrix = fem::phase_stiffness(matrix).G_L;
  Body body(mesh, mu_fibre, mu_matrix, {});  // every pair free: the open cell
  CondensedShear out;
  const Eigen::MatrixXd w_open = unit_shears(body, mesh.n_nodes());
  out.D0 = energy_modulus(mesh, mu_fibre, mu_matrix, w_open);
  if (!rows) return out;
  const int P = static_cast<int>(mesh.interface_pairs.size());
  // J w̃ per pair: w̃ at its fibre node minus at its matrix node.
  const auto jump = [&](const Eigen::VectorXd& w, int q) {
    const auto [f, m] = mesh.interface_pairs[q];
    return w(f) - w(m);
  };
  out.Y.resize(P, 2);
  for (int q = 0; q < P; ++q)
    for (int c = 0; c < 2; ++c) out.Y(q, c) = jump(w_open.col(c), q);
  out.H.resize(P, P);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(body.n_free());
  for (int p = 0; p < P; ++p) {
    const auto [f, m] = mesh.interface_pairs[p];
    // Jᵀ e_p: +1 at the fibre's node, −1 at the matrix's (a held one takes nothing).
    if (const int a = body.free(f); a >= 0) b(a) += 1;
    if (const int a = body.free(m); a >= 0) b(a) -= 1;
    const Eigen::VectorXd w = body.solve(b);
    for (int q = 0; q < P; ++q) out.H(q, p) = jump(w, q);
    b.setZero();
  }
  out.H = (0.5 * (out.H + out.H.transpose())).eval();
  // One row per piece the pairs touch (its forces sum to 0: the piece floats along z), the row
  // of the first pair's matrix piece left out (the rows of all pieces sum to 0).
  std::map<int, int> row_of;
  const int left_out = P > 0 ? body.piece(mesh.interface_pairs[0][1]) : -1;
  for (int q = 0; q < P; ++q)
    for (const int node : mesh.interface_pairs[q])
      if (const int k = body.piece(node); k != left_out && !row_of.count(k))
        row_of.emplace(k, static_cast<int>(row_of.size()));
  out.G = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(row_of.size()), P);
  for (int q = 0; q < P; ++q) {
    const auto [f, m] = mesh.interface_pairs[q];
    if (const auto it = row_of.find(body.piece(f)); it != row_of.end()) out.G(it->second, q) += 1;
    if (const auto it = row_of.find(body.piece(m)); it != row_of.end()) out.G(it->second, q) -= 1;
  }
  return out;
}

}  // namespace dualcell::primal
