#pragma once
// What Total FETI needs per mesh and material, built once and reused for every load case and
// every bond state (docs/method.md §3–§5):
//
//   symbol | variable                   | meaning
//   -------+----------------------------+-------------------------------------------------
//   K_i    | FloatingSubdomain::K       | stiffness of subdomain i (floating: ker K_i = span R_i)
//   R_i    | FloatingSubdomain::R       | orthonormal rigid-body modes (dim_i × 3)
//   K_i⁺   | FloatingSubdomain::K_plus  | fixing-node generalised inverse (linalg::FixingNodeInverse)
//   f      | FetiSetup::load(σ̄)         | tractions σ̄·n on the loaded edges + body force (edges: t·f₁)
//
// Each subdomain owns its data (no global state), so subdomains are spread over threads
// (for_each_subdomain) and over the ranks of a par::Group: each rank assembles and factorises
// only the subdomains it owns, a contiguous run balanced by DOFs (docs/method.md §16). With the
// periodic boundary a "macro" subdomain holds the macroscopic strain (εxx, εyy, γxy): K = 0,
// R = I₃, K⁺ = 0, load |Ω|·σ̄ (docs/method.md §3).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <exception>
#include <memory>
#include <vector>

#include "core/progress.hpp"
#include "core/scene.hpp"
#include "fem/element.hpp"
#include "feti/operator_cost.hpp"
#include "linalg/fixing_node_inverse.hpp"
#include "mesh/mesh.hpp"
#include "par/parallel.hpp"

namespace dualcell::feti {

// The FETI data of one subdomain of the mesh (mesh::Subdomain says which nodes and triangles).
struct FloatingSubdomain {
  int index = 0;
  bool is_fibre = false;
  bool is_macro = false;
  int dof_begin = 0;  // first global DOF
  int n_dofs = 0;
  Eigen::SparseMatrix<double> K;
  Eigen::MatrixXd R;
  std::unique_ptr<linalg::FixingNodeInverse> K_plus;  // null for the macro subdomain
  std::vector<Eigen::Index> fixing_dofs;              // the 3 DOFs removed to make K regular
  // The DOFs of the nodes that rows of B touch with intact bonds (both components; breaks remove
  // rows, never columns), sorted: for the explicit operator and the Dirichlet preconditioner.
  std::vector<Eigen::Index> boundary_dofs;
  int n_rows = 0;  // rows of B that touch it with intact bonds
  // The explicit dual operator (docs/method.md §6a): K⁺(b, b) on boundary_dofs, dense, from
  // which each bond state's F_s = B_s K⁺ B_sᵀ is formed (DualProblem); empty where implicit.
  // Without adhesion no bond ever breaks and every problem has the intact rows: their F_s is
  // formed here once (F_intact) and K⁺(b, b) released, which takes the explicit memory from b²
  // to n_rows² doubles.
  bool explicit_operator = false;
  Eigen::MatrixXd K_plus_bb, F_intact;
  // F_s = B_s K⁺ B_sᵀ = B_b K⁺(b, b) B_bᵀ from K_plus_bb, for the rows B_s (local columns).
  Eigen::MatrixXd F_of(const Eigen::SparseMatrix<double, Eigen::RowMajor>& B_s) const;
  OperatorCost cost;  // of both operators, as the choice saw them
  // The Dirichlet preconditioner only (S_i = K_bb − K_bi K_ii⁻¹ K_ib): K_ii⁻¹ as the
  // pseudo-inverse fixing exactly boundary_dofs.
  std::unique_ptr<linalg::FixingNodeInverse> K_ii_inverse;
  // Bytes of K, R and the factors held for this subdomain (0 where another rank owns it).
  std::size_t bytes() const;
  // x = K⁺ y (zero for the macro subdomain); x must have size n_dofs. scratch: n_dofs − 3
  // doubles owned by the caller, so one subdomain may be applied from any thread.
  void apply_K_plus(const Eigen::VectorXd& y, Eigen::VectorXd& x, Eigen::VectorXd& scratch) const;
};

class FetiSetup {
 public:
  // threads: how many threads share the subdomain work (assembly, factorisations, every
  // application of K⁺); 0 = as many as OpenMP offers (OMP_NUM_THREADS or the cores). Results
  // do not depend on it: each subdomain's work is done by one thread, and the contributions
  // are summed in subdomain order afterwards.
  //
  // group: the ranks that share this solve (default: this process alone). Every subdomain's R
  // and place are known on every rank; K, K⁺ and the preconditioner's factor only on its owner.
  // progress, when given, shows the phase (assembly, factorisation) while the setup works.
  // expected_qps: how many QPs the caller will solve with this setup (a sweep: its paths times
  // their loads), for the choice of dual operator per subdomain ([solver] dual_operator = "auto").
  FetiSetup(const mesh::Mesh& mesh, const Scene& scene, int threads = 1,
            int min_dofs_per_thread = default_min_dofs_per_thread, par::Group group = {}, Progress* progress = nullptr,
            double expected_qps = 1);

  const mesh::Mesh& mesh() const { return mesh_; }
  const Scene& scene() const { return scene_; }
  const std::vector<FloatingSubdomain>& subdomains() const { return subdomains_; }
  int n_dofs() const { return n_dofs_; }  // dim u (+3 macro DOFs with the periodic boundary)
  int dim_u() const { return mesh_.dim_u(); }
  int subdomain_of_dof(int dof) const { return subdomain_of_dof_[dof]; }
  const par::Group& group() const { return group_; }
  // The rank of group() that owns subdomain s, and this rank's subdomains [owned_begin, owned_end).
  int owner(int s) const { return owner_[s]; }
  bool owns(int s) const { return owner_[s] == group_.rank(); }
  int owned_begin() const { return owned_begin_; }
  int owned_end() const { return owned_end_; }
  int owned_dofs() const;
  // Bytes of the subdomain data this rank holds (K, R, the factors of its subdomains).
  std::size_t owned_bytes() const;

  // f for the macroscopic stress σ̄ = (σxx, σyy, σxy): σ̄·n on the loaded edges of the block
  // (symmetry: right and top; traction: all four; periodic: none, |Ω|σ̄ on the macro DOFs),
  // plus the scene's body force.
  // With Boundary::edges the load is one pattern, the edge tractions and point loads, scaled by
  // the load factor t = p(0) of the load coordinates p = (t, 0, 0) that take σ̄'s place; the
  // prescribed displacements scale with it (B u = t·c).
  // z: a uniform longitudinal strain ε33 (generalised plane strain, docs/method.md §3a) and a
  // temperature change ΔT: each subdomain's eigen-stress σ0 = (C13 ε33 − β ΔT)(1, 1, 0)
  // (fem::eigen_stress) adds −∫ Bᵀ σ0 dA; σ̄ is then the average of the whole in-plane stress.
  // Both 0: plane strain, the load unchanged bit for bit.
  Eigen::VectorXd load(const Eigen::Vector3d& sigma, const fem::Uniform& z = {}) const;
  // t of B u = t·c: p(0) with Boundary::edges; 1 otherwise (c = 0 there).
  double load_factor(const Eigen::Vector3d& p) const { return scene_.load.boundary == Boundary::edges ? p(0) : 1.0; }
  double volume() const { return mesh_.block_width() * mesh_.block_height(); }
  int threads() const { return threads_; }
  // Whether for_each_subdomain really spreads: only from min_dofs_per_thread DOFs per thread
  // on (a constructor argument, default_min_dofs_per_thread). Below, one application takes well
  // under a millisecond, and a parallel loop then costs more than it saves, badly so on a loaded
  // machine where a descheduled thread holds up the barrier (measured: 4×4 cells, degree 2,
  // 2 threads with a compiler on the other core: 100× slower). Results are the same either way.
  static constexpr int default_min_dofs_per_thread = 10000;
  bool parallel() const { return parallel_; }

  // work(s) for every subdomain s this rank owns, spread over threads(); work must touch only subdomain s's
  // data (its own output slots), which is what makes the result independent of the thread count.
  // An exception thrown by work is carried out of the parallel loop; the one of the lowest
  // subdomain is rethrown after all have run. Nothing is allocated unless something throws.
  template <class Work>
  void for_each_subdomain(Work&& work) const {
    const int begin = owned_begin_, end = owned_end_;
    std::exception_ptr failure;
    int failed = end;
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads_) if (parallel_)
    for (int s = begin; s < end; ++s) {
      try {
        work(s);
      } catch (...) {
#pragma omp critical(dualcell_subdomain_failure)
        if (s < failed) failed = s, failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
  }
  // The rows of B (any constraint set over these DOFs) that touch each subdomain, ascending, and
  // their block on its DOFs (local columns): B_s of F = Σ B_s K_s⁺ B_sᵀ.
  struct LocalRows {
    std::vector<int> rows;
    Eigen::SparseMatrix<double, Eigen::RowMajor> B;
  };
  std::vector<LocalRows> split_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& B) const;

  // How many of this rank's subdomains apply F explicitly, and of all ranks'; the subdomains
  // with a stiffness (all but the macro one).
  int owned_explicit() const;
  int explicit_subdomains() const { return explicit_subdomains_; }
  int n_stiff_subdomains() const { return static_cast<int>(mesh_.subdomains.size()); }
  double seconds_assembly = 0, seconds_factorisation = 0, seconds_explicit = 0;

 private:
  // FloatingSubdomain::boundary_dofs and n_rows from the rows of the intact bonds (returned).
  Eigen::SparseMatrix<double, Eigen::RowMajor> set_boundaries();
  // The constructor's steps: the ranks' subdomains (owner_), every subdomain's place and rigid
  // modes and the owned ones' stiffness, their K⁺ (and K_ii⁻¹ for the Dirichlet preconditioner),
  // and the explicit operators where they pay (or everywhere: all_explicit).
  void set_owners();
  void assemble(int min_dofs_per_thread);
  void factorise_all(bool all_explicit, bool dirichlet);
  void form_explicit_operators(const Eigen::SparseMatrix<double, Eigen::RowMajor>& intact_B, bool all_explicit,
                               double expected_qps);

  const mesh::Mesh& mesh_;
  Scene scene_;
  std::vector<FloatingSubdomain> subdomains_;
  std::vector<int> subdomain_of_dof_;
  par::Group group_;
  std::vector<int> owner_;
  int owned_begin_ = 0, owned_end_ = 0;
  int n_dofs_ = 0;
  int threads_ = 1;
  int explicit_subdomains_ = 0;
  bool parallel_ = false;
};

}  // namespace dualcell::feti
