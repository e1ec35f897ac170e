#pragma once
// What Total FETI needs per mesh and material, built once and reused for every load case and
// every bond state (METHOD §4–5):
//
//   symbol | variable                 | meaning
//   -------+--------------------------+-------------------------------------------------
//   K_i    | Subdomain::K             | stiffness of subdomain i (floating: ker K_i = span R_i)
//   R_i    | Subdomain::R             | orthonormal rigid-body modes (dim_i × 3)
//   K_i⁺   | Subdomain::K_plus        | fixing-node generalised inverse, CHOLMOD factor
//   f      | FetiSetup::load(σ̄)      | tractions σ̄·n on the loaded edges + body force
//
// Each subdomain owns its data (no global state), so subdomains can later be spread over
// threads or MPI ranks. With the periodic boundary a "macro" subdomain holds the macroscopic
// strain (εxx, εyy, γxy): K = 0, R = I₃, K⁺ = 0, load |Ω|·σ̄ (METHOD §8).
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/scene.hpp"
#include "linalg/cholmod.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::feti {

struct Subdomain {
  int index = 0;
  bool is_fibre = false;
  bool is_macro = false;
  int dof_begin = 0;   // first global DOF
  int n_dofs = 0;
  Eigen::SparseMatrix<double> K;
  Eigen::MatrixXd R;
  std::unique_ptr<linalg::FixedDofPseudoInverse> K_plus;  // null for the macro subdomain
  std::vector<Eigen::Index> fixing_dofs;                   // the 3 DOFs removed to make K regular
  // x = K⁺ y (zero for the macro subdomain). Not thread-safe per subdomain (scratch inside).
  void apply_K_plus(const Eigen::VectorXd& y, Eigen::VectorXd& x) const;
};

class FetiSetup {
 public:
  FetiSetup(const mesh::Mesh& mesh, const Scene& scene);

  const mesh::Mesh& mesh() const { return mesh_; }
  const Scene& scene() const { return scene_; }
  const std::vector<Subdomain>& subdomains() const { return subdomains_; }
  int n_dofs() const { return n_dofs_; }   // dim u (+3 macro DOFs with the periodic boundary)
  int dim_u() const { return mesh_.dim_u(); }
  int subdomain_of_dof(int dof) const { return dof_owner_[dof]; }

  // f for the macroscopic stress σ̄ = (σxx, σyy, σxy): σ̄·n on the loaded edges of the block
  // (symmetry: right and top; traction: all four; periodic: none, |Ω|σ̄ on the macro DOFs),
  // plus the scene's body force.
  Eigen::VectorXd load(const Eigen::Vector3d& sigma) const;
  double volume() const { return mesh_.block_width() * mesh_.block_height(); }
  double seconds_assembly = 0, seconds_factorisation = 0;

 private:
  const mesh::Mesh& mesh_;
  Scene scene_;
  std::vector<Subdomain> subdomains_;
  std::vector<int> dof_owner_;
  int n_dofs_ = 0;
};

}  // namespace dualcell::feti
