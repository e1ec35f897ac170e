#include "feti/dual.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "core/progress.hpp"

namespace dualcell::feti {

namespace {
// An entry of a unit eigenvector below this is round-off of the dense eigensolver.
constexpr double unit_vector_round_off = 1e-14;
}  // namespace

DualProblem::DualProblem(const FetiSetup& setup, Constraints constraints)
    : setup_(setup), constraints_(std::move(constraints)) {
  const auto& subs = setup.subdomains();
  const int n_subdomains = static_cast<int>(subs.size());
  locals_.resize(n_subdomains);

  // Split B by subdomain: which rows touch it, and the local block.
  std::vector<FetiSetup::LocalRows> split = setup.split_rows(constraints_.B);
  for (int s = 0; s < n_subdomains; ++s) {
    locals_[s].rows = std::move(split[s].rows);
    locals_[s].B = std::move(split[s].B);
  }

  // R̂_i: the rigid modes that B_i sees. The Gram matrix (B_i R_i)ᵀ(B_i R_i) is 3×3; its
  // eigenvectors with eigenvalues above round-off span what the constraints control.
  std::vector<Eigen::Triplet<double>> G_triplets;
  int G_rows = 0;
  for (int s = 0; s < n_subdomains; ++s) {
    Local& local = locals_[s];
    const int n_local = static_cast<int>(local.rows.size());
    const Eigen::MatrixXd BR = local.B * subs[s].R;
    const Eigen::Matrix3d gram = BR.transpose() * BR;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(gram);
    const double largest = eig.eigenvalues().maxCoeff();
    std::vector<int> keep;
    for (int j = 0; j < 3; ++j)
      if (eig.eigenvalues()(j) > null_mode_tolerance * largest) keep.push_back(j);
    Eigen::MatrixXd V(3, keep.size());
    for (std::size_t j = 0; j < keep.size(); ++j) V.col(j) = eig.eigenvectors().col(keep[j]);
    // Keep R itself where nothing is dropped, so that G is exactly Rᵀ Bᵀ in the usual case.
    local.V = keep.size() == 3 ? Eigen::MatrixXd(Eigen::Matrix3d::Identity()) : V;
    local.R_hat = keep.size() == 3 ? subs[s].R : Eigen::MatrixXd(subs[s].R * V);
    local.G_offset = G_rows;
    const Eigen::MatrixXd M = local.B * local.R_hat;  // n_local × r_i = (G_i)ᵀ
    for (int k = 0; k < n_local; ++k)
      for (int j = 0; j < M.cols(); ++j)
        if (M(k, j) != 0) G_triplets.emplace_back(G_rows + j, local.rows[k], M(k, j));
    G_rows += static_cast<int>(M.cols());
    if (!setup.owns(s)) continue;  // no scratch where another rank applies K⁺
    if (subs[s].explicit_operator) {
      if (subs[s].F_intact.size() > 0) {
        // No adhesion: these are the intact rows the setup formed F_s for.
        if (subs[s].F_intact.rows() != n_local)
          throw std::logic_error("explicit dual operator: subdomain " + std::to_string(s) +
                                 " has other rows than the intact ones of its F_s");
        local.F = &subs[s].F_intact;
      } else {
        local.F_own = subs[s].F_of(local.B);
        local.F = &local.F_own;
      }
    }
    local.lambda_local.resize(n_local);
    local.z.resize(n_local);
    local.y.resize(subs[s].n_dofs);
    local.x.resize(subs[s].n_dofs);
    local.K_plus_scratch.resize(subs[s].is_macro ? 0 : subs[s].K_plus->scratch_size());
    local.K_ii_scratch.resize(subs[s].K_ii_inverse ? subs[s].K_ii_inverse->scratch_size() : 0);
  }
  G_.resize(G_rows, constraints_.n_rows());
  G_.setFromTriplets(G_triplets.begin(), G_triplets.end());
  set_exchange();

  if (setup.scene().solver.preconditioner != Preconditioner::none) set_preconditioner_scale();

  // (DG)(DG)ᵀ: small (3 per subdomain) and sparse (neighbours only); factorised once.
  G_row_scale_ = Eigen::VectorXd::Ones(G_rows);
  for (int i = 0; i < G_rows; ++i) {
    const double length = G_.row(i).norm();
    if (length > 0) G_row_scale_(i) = 1 / length;
  }
  DG_ = G_row_scale_.asDiagonal() * G_;
  const Eigen::SparseMatrix<double> GGt = Eigen::SparseMatrix<double>(DG_ * DG_.transpose());
  GGt_ = linalg::SparseCholesky(linalg::CholmodOptions{linalg::FactorKind::simplicial});
  try {
    GGt_.compute(GGt);
  } catch (const linalg::CholeskyError&) {
    GGt_ = linalg::SparseCholesky(linalg::CholmodOptions{linalg::FactorKind::simplicial});
    GGt_.compute(with_joint_null_modes(GGt));
  }
  G_scratch_.resize(G_rows);
  G_solution_.resize(G_rows);
}

NullSplit split_null_space(const Eigen::MatrixXd& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
  NullSplit out;
  out.largest = eig.eigenvalues().size() > 0 ? eig.eigenvalues().maxCoeff() : 0;
  std::vector<Eigen::Index> range, null;
  for (Eigen::Index j = 0; j < eig.eigenvalues().size(); ++j)
    (eig.eigenvalues()(j) > null_mode_tolerance * out.largest ? range : null).push_back(j);
  out.range = eig.eigenvectors()(Eigen::all, range);
  out.null = eig.eigenvectors()(Eigen::all, null);
  return out;
}

// A rigid motion that the rows of each subdomain see but that no row sees jointly across
// subdomains leaves GGᵀ singular: the spin of an RVE's fibre cut by the edges about its centre,
// its pieces turning together, seen by neither the normal rows (through the centre) nor the
// periodic rows between the pieces (which move alike). The motion is undetermined, as a whole
// fibre's spin is (R̂ drops that one). Its null vectors Z (of the small coarse matrix, found
// densely) are added as Z Zᵀ: on the range of G, where every coarse right-hand side lies, the
// factor of GGᵀ + Z Zᵀ is the pseudo-inverse of GGᵀ, and the undetermined amplitude is 0.
Eigen::SparseMatrix<double> DualProblem::with_joint_null_modes(const Eigen::SparseMatrix<double>& GGt) {
  // A limit of the input, as the condensation's row limit: 6000 coarse rows (3 per subdomain) are
  // a dense symmetric eigenproblem of 288 MB, O(n³) work.
  constexpr Eigen::Index dense_limit = 6000;
  if (GGt.rows() > dense_limit)
    throw InputError(
        "the coarse matrix GG^T is singular (a rigid motion no row sees: an RVE's fibre cut by the "
        "edges) and has " +
        std::to_string(GGt.rows()) + " rows, more than the " + std::to_string(dense_limit) +
        " whose null space is found densely: use larger subdomains ([solver] subdomain_dofs)");
  const NullSplit split = split_null_space(Eigen::MatrixXd(GGt));
  const double largest = split.largest;
  Eigen::SparseMatrix<double> out = GGt;
  for (Eigen::Index j = 0; j < split.null.cols(); ++j) {
    const Eigen::VectorXd z = split.null.col(j);
    // A cut fibre's pieces: a few entries; the others are the eigensolver's round-off (of a unit
    // vector), left out so that Z Zᵀ stays as sparse as GGᵀ.
    std::vector<Eigen::Index> support;
    for (Eigen::Index a = 0; a < z.size(); ++a)
      if (std::abs(z(a)) > unit_vector_round_off) support.push_back(a);
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index a : support)
      for (Eigen::Index b : support) t.emplace_back(a, b, largest * z(a) * z(b));
    Eigen::SparseMatrix<double> zzt(GGt.rows(), GGt.cols());
    zzt.setFromTriplets(t.begin(), t.end());
    out += zzt;
  }
  return out;
}

void DualProblem::set_exchange() {
  const par::Group& group = setup_.group();
  const int P = group.size();
  const auto& subs = setup_.subdomains();
  Exchange& ex = exchange_;
  ex.counts.assign(P, 0);
  ex.displs.assign(P, 0);
  ex.dof_counts.assign(P, 0);
  ex.dof_displs.assign(P, 0);
  ex.row.clear();
  // Ownership is contiguous in subdomain order (FetiSetup), and so are the subdomains' DOFs.
  int s = 0;
  const int n_subdomains = static_cast<int>(subs.size());
  for (int p = 0; p < P; ++p) {
    const int begin = s;
    while (s < n_subdomains && setup_.owner(s) == p) ++s;
    std::vector<int> rows;
    for (int i = begin; i < s; ++i) rows.insert(rows.end(), locals_[i].rows.begin(), locals_[i].rows.end());
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    ex.displs[p] = static_cast<int>(ex.row.size());
    ex.counts[p] = static_cast<int>(rows.size());
    ex.row.insert(ex.row.end(), rows.begin(), rows.end());
    ex.dof_displs[p] = begin < n_subdomains ? subs[begin].dof_begin : setup_.n_dofs();
    ex.dof_counts[p] = begin < s ? subs[s - 1].dof_begin + subs[s - 1].n_dofs - subs[begin].dof_begin : 0;
    if (p == group.rank())
      for (int i = begin; i < s; ++i) {
        Local& local = locals_[i];
        local.slot.resize(local.rows.size());
        for (std::size_t k = 0; k < local.rows.size(); ++k)
          local.slot[k] = static_cast<int>(std::lower_bound(rows.begin(), rows.end(), local.rows[k]) - rows.begin());
      }
  }
  if (s != n_subdomains) throw std::logic_error("DualProblem: subdomain owners are not contiguous in rank order");
  ex.all.resize(static_cast<Eigen::Index>(ex.row.size()));
}

namespace {
using Clock = std::chrono::steady_clock;
// Adds the lifetime of the object to `total`.
class ScopedTimer {
 public:
  explicit ScopedTimer(double& total) : total_(total), start_(Clock::now()) {}
  ~ScopedTimer() { total_ += seconds_since(start_); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double& total_;
  Clock::time_point start_;
};
}  // namespace

void DualProblem::add_row_sums(Eigen::VectorXd& y, bool skip_macro) const {
  const par::Group& group = setup_.group();
  const auto& subs = setup_.subdomains();
  const Exchange& ex = exchange_;
  const int me = group.rank();
  auto mine = ex.all.segment(ex.displs[me], ex.counts[me]);
  mine.setZero();
  for (int s = setup_.owned_begin(); s < setup_.owned_end(); ++s) {
    if (skip_macro && subs[s].is_macro) continue;
    const Local& local = locals_[s];
    for (std::size_t k = 0; k < local.rows.size(); ++k) mine(local.slot[k]) += local.z(k);
  }
  if (group.size() > 1) {
    const ScopedTimer timer(profile_.communication);
    group.gather(mine.data(), ex.all.data(), ex.counts, ex.displs);
    ++profile_.exchanges;
    profile_.bytes_received += static_cast<double>(sizeof(double)) * static_cast<double>(ex.all.size() - mine.size());
  }
  for (Eigen::Index i = 0; i < ex.all.size(); ++i) y(ex.row[i]) += ex.all(i);
}

void DualProblem::apply_F(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const ScopedTimer timer(profile_.F);
  const auto& subs = setup_.subdomains();
  setup_.for_each_subdomain([&](int s) {
    const Local& local = locals_[s];
    if (local.rows.empty()) return;
    for (std::size_t k = 0; k < local.rows.size(); ++k) local.lambda_local(k) = x(local.rows[k]);
    if (subs[s].explicit_operator) {
      local.z.noalias() = *local.F * local.lambda_local;
      return;
    }
    local.y.noalias() = local.B.transpose() * local.lambda_local;
    subs[s].apply_K_plus(local.y, local.x, local.K_plus_scratch);
    local.z.noalias() = local.B * local.x;
  });
  y.setZero();
  add_row_sums(y, false);
}

void DualProblem::set_preconditioner_scale() {
  const auto& subs = setup_.subdomains();
  const int m = constraints_.n_rows();
  // k_ri = Σ b² K_dd / Σ b² over the row's entries in subdomain i (the weight w cancels), on
  // the rank that owns i; Σ_j 1/k_rj over every rank.
  std::vector<std::vector<double>> k(locals_.size());
  Eigen::VectorXd compliance_sum = Eigen::VectorXd::Zero(m);
  for (int s = setup_.owned_begin(); s < setup_.owned_end(); ++s) {
    Local& local = locals_[s];
    k[s].assign(local.rows.size(), 0.0);
    local.z.setZero();
    if (subs[s].is_macro) continue;
    const Eigen::VectorXd K_diagonal = subs[s].K.diagonal();
    if (subs[s].K_ii_inverse) {
      // S_i lives on the boundary DOFs: every DOF a row touches must be one of them.
      std::vector<char> on_boundary(subs[s].n_dofs, 0);
      for (Eigen::Index d : subs[s].boundary_dofs) on_boundary[d] = 1;
      for (int r = 0; r < local.B.outerSize(); ++r)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(local.B, r); it; ++it)
          if (!on_boundary[it.col()])
            throw std::logic_error("Dirichlet preconditioner: a constraint row touches an interior DOF of subdomain " +
                                   std::to_string(s));
    }
    for (int r = 0; r < local.B.outerSize(); ++r) {
      double bb = 0, bKb = 0;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(local.B, r); it; ++it) {
        bb += it.value() * it.value();
        bKb += it.value() * it.value() * K_diagonal(it.col());
      }
      if (bb > 0 && bKb > 0) {
        k[s][r] = bKb / bb;
        local.z(r) = 1 / k[s][r];
      }
    }
  }
  add_row_sums(compliance_sum, true);
  for (int s = setup_.owned_begin(); s < setup_.owned_end(); ++s) {
    Local& local = locals_[s];
    local.preconditioner_scale = Eigen::VectorXd::Zero(local.rows.size());
    for (std::size_t r = 0; r < local.rows.size(); ++r) {
      const int row = local.rows[r];
      const double w = constraints_.weight(row);
      if (k[s][r] > 0) local.preconditioner_scale(r) = (1 / k[s][r]) / compliance_sum(row) / (w * w);
    }
  }
}

void DualProblem::apply_preconditioner(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const ScopedTimer timer(profile_.preconditioner);
  if (setup_.scene().solver.preconditioner == Preconditioner::none)
    throw std::logic_error("DualProblem::apply_preconditioner: the scene has preconditioner = none");
  const auto& subs = setup_.subdomains();
  const bool dirichlet = setup_.scene().solver.preconditioner == Preconditioner::dirichlet;
  setup_.for_each_subdomain([&](int s) {
    const Local& local = locals_[s];
    if (local.rows.empty() || subs[s].is_macro) return;
    for (std::size_t k = 0; k < local.rows.size(); ++k)
      local.lambda_local(k) = local.preconditioner_scale(k) * x(local.rows[k]);
    local.y.noalias() = local.B.transpose() * local.lambda_local;  // on boundary DOFs only
    if (dirichlet) {
      // S_i y = (K (y − K_ii⁻¹(K y)_I))_B: eliminate the interior, then the boundary reaction.
      local.x.noalias() = subs[s].K * local.y;
      subs[s].K_ii_inverse->apply(local.x, local.x, local.K_ii_scratch);  // zero on the boundary
      local.y -= local.x;
    }
    local.x.noalias() = subs[s].K * local.y;
    local.z.noalias() = local.B * local.x;
    local.z.array() *= local.preconditioner_scale.array();
  });
  y.setZero();
  add_row_sums(y, true);
}

void DualProblem::apply_Q(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const ScopedTimer timer(profile_.Q);
  G_scratch_.noalias() = DG_ * x;
  GGt_.solve(G_scratch_, G_solution_);
  y.noalias() = DG_.transpose() * G_solution_;
}

Eigen::VectorXd DualProblem::d(const Eigen::VectorXd& f, double t) const {
  // Timed with F: one application of B K⁺, whose exchange counts in `communication` like F's.
  const ScopedTimer timer(profile_.F);
  const auto& subs = setup_.subdomains();
  setup_.for_each_subdomain([&](int s) {
    const Local& local = locals_[s];
    local.y = f.segment(subs[s].dof_begin, subs[s].n_dofs);
    subs[s].apply_K_plus(local.y, local.x, local.K_plus_scratch);
    local.z.noalias() = local.B * local.x;
  });
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n_rows());
  add_row_sums(d, false);
  d -= t * constraints_.c;  // after the sum, so that its order is the same on any number of ranks
  return d;
}

Eigen::VectorXd DualProblem::e(const Eigen::VectorXd& f) const {
  Eigen::VectorXd e(n_G_rows());
  const auto& subs = setup_.subdomains();
  for (std::size_t s = 0; s < locals_.size(); ++s) {
    const Local& local = locals_[s];
    e.segment(local.G_offset, local.R_hat.cols()) =
        local.R_hat.transpose() * f.segment(subs[s].dof_begin, subs[s].n_dofs);
  }
  return e;
}

// λ₀ = Gᵀ(GGᵀ)⁻¹e = (DG)ᵀ((DG)(DG)ᵀ)⁻¹ D e.
Eigen::VectorXd DualProblem::lambda_0(const Eigen::VectorXd& e) const {
  G_scratch_ = G_row_scale_.cwiseProduct(e);
  GGt_.solve(G_scratch_, G_solution_);
  return DG_.transpose() * G_solution_;
}

Eigen::VectorXd DualProblem::coarse_solve(const Eigen::VectorXd& r) const {
  // (GGᵀ)⁻¹G r = D ((DG)(DG)ᵀ)⁻¹ (DG) r.
  G_scratch_.noalias() = DG_ * r;
  Eigen::VectorXd alpha_hat;
  GGt_.solve(G_scratch_, alpha_hat);
  return G_row_scale_.cwiseProduct(alpha_hat);
}

Eigen::MatrixXd DualProblem::explicit_F() const {
  const auto& subs = setup_.subdomains();
  const par::Group& group = setup_.group();
  // This rank's F_s, column-major one after another in subdomain order.
  std::vector<double> mine;
  for (int s = setup_.owned_begin(); s < setup_.owned_end(); ++s) {
    const Local& local = locals_[s];
    const auto n = static_cast<Eigen::Index>(local.rows.size());
    if (subs[s].is_macro || n == 0) continue;
    Eigen::MatrixXd F_s;
    if (subs[s].explicit_operator) {
      F_s = *local.F;
    } else {
      F_s.resize(n, n);
      Eigen::VectorXd unit = Eigen::VectorXd::Zero(n);
      for (Eigen::Index j = 0; j < n; ++j) {
        unit(j) = 1;
        local.y.noalias() = local.B.transpose() * unit;
        subs[s].apply_K_plus(local.y, local.x, local.K_plus_scratch);
        F_s.col(j).noalias() = local.B * local.x;
        unit(j) = 0;
      }
    }
    mine.insert(mine.end(), F_s.data(), F_s.data() + F_s.size());
  }
  std::vector<double> all = mine;
  if (group.size() > 1) {
    const std::vector<double> sizes = group.gather(std::vector<double>{static_cast<double>(mine.size())});
    std::vector<int> counts(sizes.size()), displs(sizes.size(), 0);
    for (std::size_t p = 0; p < sizes.size(); ++p) {
      counts[p] = static_cast<int>(sizes[p]);
      if (p > 0) displs[p] = displs[p - 1] + counts[p - 1];
    }
    all.resize(static_cast<std::size_t>(displs.back() + counts.back()));
    group.gather(mine.data(), all.data(), counts, displs);
  }
  const int m = n_rows();
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(m, m);
  std::size_t at = 0;
  for (std::size_t s = 0; s < locals_.size(); ++s) {
    const Local& local = locals_[s];
    const std::size_t n = local.rows.size();
    if (subs[s].is_macro || n == 0) continue;
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < n; ++i) F(local.rows[i], local.rows[j]) += all[at + j * n + i];
    at += n * n;
  }
  return F;
}

Eigen::VectorXd DualProblem::K_plus_residual(const Eigen::VectorXd& f, const Eigen::VectorXd& lambda) const {
  Eigen::VectorXd u(setup_.n_dofs());
  const auto& subs = setup_.subdomains();
  setup_.for_each_subdomain([&](int s) {
    const Local& local = locals_[s];
    for (std::size_t k = 0; k < local.rows.size(); ++k) local.lambda_local(k) = lambda(local.rows[k]);
    local.y = f.segment(subs[s].dof_begin, subs[s].n_dofs);
    if (!local.rows.empty()) local.y.noalias() -= local.B.transpose() * local.lambda_local;
    subs[s].apply_K_plus(local.y, local.x, local.K_plus_scratch);
    u.segment(subs[s].dof_begin, subs[s].n_dofs) = local.x;  // disjoint segments
  });
  const Exchange& ex = exchange_;
  const int me = setup_.group().rank();
  setup_.group().gather(u.data() + ex.dof_displs[me], u.data(), ex.dof_counts, ex.dof_displs);
  return u;
}

}  // namespace dualcell::feti
