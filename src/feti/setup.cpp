#include "feti/setup.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>

#include "core/progress.hpp"
#include "fem/assembly.hpp"
#include "fem/element.hpp"
#include "feti/constraints.hpp"

namespace dualcell::feti {

namespace {

using Clock = std::chrono::steady_clock;

// Fixing nodes (docs/method.md §5): node a far from the centroid, node b far from a; fix both
// components of a and the component of b across the line ab, which removes the rotation.
std::vector<Eigen::Index> fixing_dofs(const mesh::Mesh& mesh, const mesh::Subdomain& sub) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (int v = sub.node_begin; v < sub.node_end; ++v) centroid += mesh.nodes[v];
  centroid /= sub.n_nodes();
  auto farthest_from = [&](const Eigen::Vector2d& p) {
    int best = sub.node_begin;
    for (int v = sub.node_begin; v < sub.node_end; ++v)
      if ((mesh.nodes[v] - p).squaredNorm() > (mesh.nodes[best] - p).squaredNorm()) best = v;
    return best;
  };
  const int a = farthest_from(centroid);
  const int b = farthest_from(mesh.nodes[a]);
  const Eigen::Vector2d ab = mesh.nodes[b] - mesh.nodes[a];
  const int across = std::abs(ab.x()) >= std::abs(ab.y()) ? 1 : 0;  // y when ab is mostly along x
  const Eigen::Index la = a - sub.node_begin, lb = b - sub.node_begin;
  return {2 * la, 2 * la + 1, 2 * lb + across};
}

}  // namespace

std::size_t FloatingSubdomain::bytes() const {
  const auto sparse = [](const Eigen::SparseMatrix<double>& A) {
    return static_cast<std::size_t>(A.nonZeros()) * (sizeof(double) + sizeof(int)) + (A.outerSize() + 1) * sizeof(int);
  };
  std::size_t total = sparse(K) + static_cast<std::size_t>(R.size()) * sizeof(double);
  if (K_plus) total += K_plus->bytes();
  if (K_ii_inverse) total += K_ii_inverse->bytes();
  total += static_cast<std::size_t>(K_plus_bb.size() + F_intact.size()) * sizeof(double);
  return total;
}

int FetiSetup::owned_dofs() const {
  int n = 0;
  for (int s = owned_begin_; s < owned_end_; ++s) n += subdomains_[s].n_dofs;
  return n;
}

int FetiSetup::owned_explicit() const {
  int n = 0;
  for (int s = owned_begin_; s < owned_end_; ++s) n += subdomains_[s].explicit_operator ? 1 : 0;
  return n;
}

std::size_t FetiSetup::owned_bytes() const {
  std::size_t n = 0;
  for (int s = owned_begin_; s < owned_end_; ++s) n += subdomains_[s].bytes();
  return n;
}

void FloatingSubdomain::apply_K_plus(const Eigen::VectorXd& y, Eigen::VectorXd& x, Eigen::VectorXd& scratch) const {
  if (is_macro) {
    x.setZero();
    return;
  }
  K_plus->apply(y, x, scratch);
}

FetiSetup::FetiSetup(const mesh::Mesh& mesh, const Scene& scene, int threads, int min_dofs_per_thread, par::Group group,
                     Progress* progress, double expected_qps)
    : mesh_(mesh), scene_(scene), group_(std::move(group)), threads_(threads > 0 ? threads : omp_get_max_threads()) {
  validate(scene_);  // scenes built in code are checked like scenes read from a file
  const auto phase = [&](const char* name) {
    if (progress) progress->update([&] { return std::string(name) + ", " + seconds_text(progress->seconds()); });
  };
  phase("assembly");
  const auto t0 = Clock::now();
  const bool periodic = scene.load.boundary == Boundary::periodic;
  subdomains_.resize(mesh.subdomains.size() + (periodic ? 1 : 0));
  n_dofs_ = mesh.dim_u() + (periodic ? 3 : 0);
  set_owners();
  assemble(min_dofs_per_thread);
  seconds_assembly = seconds_since(t0);

  const DualOperator dual_operator = scene.solver.dual_operator;
  const bool dirichlet = scene.solver.preconditioner == Preconditioner::dirichlet;
  Eigen::SparseMatrix<double, Eigen::RowMajor> intact_B;
  if (dirichlet || dual_operator != DualOperator::implicit) intact_B = set_boundaries();
  const auto t1 = Clock::now();
  phase("factorisation");
  factorise_all(dual_operator == DualOperator::explicit_, dirichlet);
  seconds_factorisation = seconds_since(t1);

  // The explicit operators where they pay (everywhere, or nowhere, as the scene says).
  if (dual_operator == DualOperator::implicit) return;
  const auto t2 = Clock::now();
  phase("explicit dual operators");
  form_explicit_operators(intact_B, dual_operator == DualOperator::explicit_, expected_qps);
  seconds_explicit = seconds_since(t2);
  for (double n : group_.gather(std::vector<double>{static_cast<double>(owned_explicit())}))
    explicit_subdomains_ += static_cast<int>(n);
}

void FetiSetup::set_owners() {
  const mesh::Mesh& mesh = mesh_;
  const int n_subdomains = static_cast<int>(mesh.subdomains.size());
  // Owners: contiguous runs of subdomains, balanced by DOFs (the factorisation and every K⁺
  // grow with them); a subdomain goes to the rank its middle DOF falls in. Contiguous and in
  // rank order, so that a sum over a row's subdomains in subdomain order is a sum of the ranks'
  // partial sums in rank order (DualProblem::RowSums). The macro subdomain goes to the last rank.
  const int P = group_.size();
  owner_.assign(subdomains_.size(), P - 1);
  for (int s = 0; s < n_subdomains; ++s) {
    const double middle = 2.0 * mesh.subdomains[s].node_begin + mesh.subdomains[s].n_nodes();
    owner_[s] = std::min(P - 1, static_cast<int>(P * middle / mesh.dim_u()));
  }
  owned_begin_ = static_cast<int>(std::find(owner_.begin(), owner_.end(), group_.rank()) - owner_.begin());
  owned_end_ = static_cast<int>(
      std::find_if(owner_.begin() + owned_begin_, owner_.end(), [&](int r) { return r != group_.rank(); }) -
      owner_.begin());
}

void FetiSetup::assemble(int min_dofs_per_thread) {
  const mesh::Mesh& mesh = mesh_;
  const Scene& scene = scene_;
  const int n_subdomains = static_cast<int>(mesh.subdomains.size());
  const bool periodic = scene.load.boundary == Boundary::periodic;
  // Every rank knows every subdomain's place and rigid modes (G is built from them); the
  // stiffness only where it is owned.
  for (int s = 0; s < n_subdomains; ++s) {
    const mesh::Subdomain& ms = mesh.subdomains[s];
    FloatingSubdomain& sub = subdomains_[s];
    sub.index = s;
    sub.is_fibre = ms.is_fibre;
    sub.dof_begin = 2 * ms.node_begin;
    sub.n_dofs = 2 * ms.n_nodes();
    sub.R = fem::rigid_body_modes(mesh, s);
  }
  // Threads over this rank's subdomains once they have enough DOFs to share (n_dofs is known
  // from here on).
  parallel_ = threads_ > 1 && owned_dofs() >= static_cast<long>(min_dofs_per_thread) * threads_;
  for_each_subdomain([&](int s) {
    if (s >= n_subdomains) return;
    const mesh::Subdomain& ms = mesh.subdomains[s];
    FloatingSubdomain& sub = subdomains_[s];
    sub.K = fem::assemble_stiffness(mesh, s, ms.is_fibre ? scene.fibre : scene.matrix);
    sub.fixing_dofs = fixing_dofs(mesh, ms);
  });
  if (periodic) {
    FloatingSubdomain& macro = subdomains_[n_subdomains];
    macro.index = n_subdomains;
    macro.is_macro = true;
    macro.dof_begin = mesh.dim_u();
    macro.n_dofs = 3;
    macro.K.resize(3, 3);
    macro.R = Eigen::MatrixXd::Identity(3, 3);
  }
  subdomain_of_dof_.assign(n_dofs_, -1);
  for (const FloatingSubdomain& sub : subdomains_)
    for (int d = 0; d < sub.n_dofs; ++d) subdomain_of_dof_[sub.dof_begin + d] = sub.index;
}

namespace {

// K⁺ once per mesh and material: the factorisations every load case reuses. Subdomains are
// small (hundreds to a few thousand DOFs), where a simplicial factor is as fast as a supernodal
// one and needs no BLAS; K⁺ is then applied with plain triangular sweeps. AMD only: the
// factorisations run concurrently, and METIS's random state is not known to be thread-safe. (A
// supernodal factor's many small BLAS calls were measured slower here, and erratic: OpenBLAS's
// threads yielding on a shared machine.)
const linalg::CholmodOptions subdomain_factor_options{linalg::FactorKind::simplicial, linalg::Ordering::amd};

// K⁺ of sub, with its boundary DOFs ordered last when the explicit operator needs them there.
void factorise(FloatingSubdomain& sub, bool boundary_last) {
  const std::span<const Eigen::Index> last =
      boundary_last ? std::span<const Eigen::Index>(sub.boundary_dofs) : std::span<const Eigen::Index>();
  sub.K_plus = std::make_unique<linalg::FixingNodeInverse>(sub.K, sub.fixing_dofs, subdomain_factor_options, last);
}

}  // namespace

void FetiSetup::factorise_all(bool all_explicit, bool dirichlet) {
  for_each_subdomain([&](int s) {
    FloatingSubdomain& sub = subdomains_[s];
    if (sub.is_macro) return;
    factorise(sub, all_explicit);
    if (dirichlet)
      sub.K_ii_inverse =
          std::make_unique<linalg::FixingNodeInverse>(sub.K, sub.boundary_dofs, subdomain_factor_options);
  });
}

void FetiSetup::form_explicit_operators(const Eigen::SparseMatrix<double, Eigen::RowMajor>& intact_B, bool all_explicit,
                                        double expected_qps) {
  const Scene& scene = scene_;
  // The factor again with the boundary DOFs last (already so with "explicit"), then K⁺(b, b).
  const bool fixed_rows = !scene.interface.has_adhesion();
  const std::vector<LocalRows> intact_rows = fixed_rows ? split_rows(intact_B) : std::vector<LocalRows>();
  for_each_subdomain([&](int s) {
    FloatingSubdomain& sub = subdomains_[s];
    if (sub.is_macro) return;
    sub.cost = OperatorCost::of(*sub.K_plus, sub.n_rows, static_cast<Eigen::Index>(sub.boundary_dofs.size()));
    sub.explicit_operator = all_explicit || sub.cost.explicit_pays(expected_qps);
    if (!sub.explicit_operator) return;
    if (!all_explicit) factorise(sub, true);
    sub.K_plus_bb = sub.K_plus->last_block_inverse();
    if (fixed_rows) {
      sub.F_intact = sub.F_of(intact_rows[s].B);
      sub.K_plus_bb = Eigen::MatrixXd();
    }
  });
}

std::vector<FetiSetup::LocalRows> FetiSetup::split_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& B) const {
  std::vector<LocalRows> out(subdomains_.size());
  std::vector<std::vector<Eigen::Triplet<double>>> triplets(subdomains_.size());
  for (int r = 0; r < B.rows(); ++r)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(B, r); it; ++it) {
      const int s = subdomain_of_dof_[it.col()];
      LocalRows& local = out[s];
      if (local.rows.empty() || local.rows.back() != r) local.rows.push_back(r);
      triplets[s].emplace_back(static_cast<int>(local.rows.size()) - 1,
                               static_cast<int>(it.col()) - subdomains_[s].dof_begin, it.value());
    }
  for (std::size_t s = 0; s < out.size(); ++s) {
    out[s].B.resize(static_cast<Eigen::Index>(out[s].rows.size()), subdomains_[s].n_dofs);
    out[s].B.setFromTriplets(triplets[s].begin(), triplets[s].end());
  }
  return out;
}

Eigen::MatrixXd FloatingSubdomain::F_of(const Eigen::SparseMatrix<double, Eigen::RowMajor>& B_s) const {
  // Every DOF a row touches is a boundary DOF (FetiSetup::set_boundaries): B_b is B_s on them.
  std::vector<int> position(n_dofs, -1);
  for (std::size_t k = 0; k < boundary_dofs.size(); ++k) position[boundary_dofs[k]] = static_cast<int>(k);
  std::vector<Eigen::Triplet<double>> entries;
  for (int r = 0; r < B_s.outerSize(); ++r)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(B_s, r); it; ++it) {
      if (position[it.col()] < 0)
        throw std::logic_error("explicit dual operator: a row touches an interior DOF of subdomain " +
                               std::to_string(index));
      entries.emplace_back(r, position[it.col()], it.value());
    }
  Eigen::SparseMatrix<double, Eigen::RowMajor> B_b(B_s.rows(), static_cast<Eigen::Index>(boundary_dofs.size()));
  B_b.setFromTriplets(entries.begin(), entries.end());
  const Eigen::MatrixXd BK = B_b * K_plus_bb;
  const Eigen::MatrixXd F = BK * B_b.transpose();
  return 0.5 * (F + F.transpose());  // symmetric to the last bit, as the QP's CG assumes
}

Eigen::SparseMatrix<double, Eigen::RowMajor> FetiSetup::set_boundaries() {
  // The nodes B touches with intact bonds (breaks remove rows, never columns), both
  // components: a free or loaded edge stays interior, where S_i must not clamp it.
  const Constraints rows = build_constraints(mesh_, scene_, intact_bonds(mesh_, scene_.interface));
  std::vector<char> on_boundary(mesh_.nodes.size(), 0);
  std::vector<int> last_row(subdomains_.size(), -1);
  for (int r = 0; r < rows.B.outerSize(); ++r)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows.B, r); it; ++it) {
      FloatingSubdomain& sub = subdomains_[subdomain_of_dof_[it.col()]];
      if (last_row[sub.index] != r) ++sub.n_rows, last_row[sub.index] = r;
      if (it.col() < mesh_.dim_u()) on_boundary[it.col() / 2] = 1;  // not the macro DOFs
    }
  for_each_subdomain([&](int s) {
    FloatingSubdomain& sub = subdomains_[s];
    if (sub.is_macro) return;
    const mesh::Subdomain& ms = mesh_.subdomains[s];
    for (int v = ms.node_begin; v < ms.node_end; ++v)
      if (on_boundary[v]) {
        sub.boundary_dofs.push_back(2 * (v - ms.node_begin));
        sub.boundary_dofs.push_back(2 * (v - ms.node_begin) + 1);
      }
  });
  return rows.B;
}

Eigen::VectorXd FetiSetup::load(const Eigen::Vector3d& sigma, const fem::Uniform& z) const {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n_dofs_);
  Eigen::Matrix2d sigma_bar;
  sigma_bar << sigma(0), sigma(2), sigma(2), sigma(1);
  std::vector<int> sides;
  switch (scene_.load.boundary) {
    case Boundary::symmetry:
      sides = {mesh::right, mesh::top};
      break;
    case Boundary::traction:
      sides = {mesh::left, mesh::right, mesh::bottom, mesh::top};
      break;
    case Boundary::periodic:
      f.tail<3>() = volume() * sigma;
      break;
    case Boundary::edges: {
      // Tractions linear along each edge from its start (bottom or left end) to its end, and
      // point loads, at load factor t = sigma(0).
      const EdgeLoads& loads = scene_.load.edge_loads;
      const double t = sigma(0);
      for (int e = 0; e < 4; ++e) {
        const EdgeCondition& c = loads.edges[e];
        if (c.kind != EdgeKind::traction) continue;
        const int along = e < 2 ? 1 : 0;
        const double length = along == 1 ? mesh_.block_height() : mesh_.block_width();
        const auto at = [&](int v) { return (t * c.traction_at(mesh_.nodes[v](along) / length)).eval(); };
        for (const mesh::Edge& edge : mesh_.boundary_edges[edge_sides[e]])
          fem::add_edge_traction(mesh_, edge, at(edge.a), at(edge.b), f);
      }
      for (const PointLoad& p : loads.point_loads)
        f.segment<2>(2 * node_at(mesh_, p.at, p.where, "point load")) += t * p.force;
      break;
    }
  }
  for (int side : sides)
    for (const mesh::Edge& edge : mesh_.boundary_edges[side]) {
      const Eigen::Vector2d e = mesh_.nodes[edge.b] - mesh_.nodes[edge.a];  // the outer edges are straight
      const Eigen::Vector2d t = sigma_bar * Eigen::Vector2d(e.y(), -e.x()).normalized();
      fem::add_edge_traction(mesh_, edge, t, t, f);
    }
  const Eigen::Vector2d body(scene_.load.body_force[0], scene_.load.body_force[1]);
  if (body.squaredNorm() > 0)
    for (int s = 0; s < static_cast<int>(mesh_.subdomains.size()); ++s) fem::add_body_force(mesh_, s, body, f);
  if (!z.zero())
    for (int s = 0; s < static_cast<int>(mesh_.subdomains.size()); ++s) {
      const fem::PhaseStiffness P = fem::phase_stiffness(mesh_.subdomains[s].is_fibre ? scene_.fibre : scene_.matrix);
      fem::add_eigen_stress(mesh_, s, fem::eigen_stress(P, z), f);
    }
  return f;
}

}  // namespace dualcell::feti
