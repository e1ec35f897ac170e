#pragma once
// The state of a HomogenisedStructure (structure.hpp), shared by its files: structure.cpp (the
// facade, the points' laws and bonds, the fuse), setup.cpp (quadrature, constraints, loads, the
// tangent's pattern) and newton.cpp (the energy and Newton's method with its line search).
#include <Eigen/SparseCore>

#include "linalg/sparse_cholesky.hpp"
#include "structure/structure.hpp"

namespace dualcell::structure {

struct Point {
  Eigen::MatrixXd grad_s;  // ∇ˢ: the strain-displacement matrix, ε = ∇ˢ u_e (docs/method.md §3)
  double weight;
};

struct HomogenisedStructure::Impl {
  Progress* progress = nullptr;
  StructureScene scene;
  CellLaw law;
  StructureMesh mesh;
  int n_dofs = 0, per = 3;
  int n_free = 0;                          // DOFs not held by an edge or support
  std::vector<std::vector<Point>> points;  // per triangle
  std::vector<int> first_point;            // per triangle: the index of its first point (T + 1 entries)
  // The state of every point at the displacements last evaluated (evaluate_points), and with the
  // exact law each point's bond history and, per thread, an evaluator.
  std::vector<law::ConeState> state;
  std::vector<law::CellHistory> history;       // per point
  std::vector<law::CellHistory> cell_history;  // per cell, when the bonds are the cell's (bond_unit)
  std::vector<std::vector<int>> cell_triangles;
  std::vector<double> strength_use;  // per point, exact law: CellResponse::strength_use
  std::vector<std::unique_ptr<law::CellEvaluator>> evaluators;
  int threads = 1;                                  // the exact law's evaluators: one per OpenMP thread
  law::BondMode trial_bonds = law::BondMode::held;  // what a Newton iterate does with the bonds
  // An exact-law evaluation failed (its QP) in the step being solved, and why: the step is then
  // not converged and says so (StepResult::message).
  bool point_failed = false;
  std::string point_failure;
  std::vector<Eigen::MatrixXd> grad_s_centroid;
  std::vector<double> area;
  std::vector<int> free_index;      // per DOF: its index among the free DOFs, or −1
  std::vector<int> constrained_by;  // per DOF: 0..3 an edge, 4 a support, −1 free
  Eigen::VectorXd prescribed;       // per DOF: the value at factor 1 (0 where free)
  Eigen::VectorXd f;                // external load at factor 1, all DOFs
  std::vector<std::uint8_t> cell_fused;
  Eigen::VectorXd u;
  // The tangent's fixed pattern (lower triangle over the free DOFs) and, per triangle, the slot
  // in its value array of each lower entry (a ≥ b) of the element matrix (−1: a constrained DOF).
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> K;
  std::vector<std::vector<int>> slot;
  linalg::SparseCholesky cholesky;
  Eigen::VectorXd r_full, f_int, step, trial;

  int dof(int triangle, int a) const { return 2 * mesh.triangles(triangle, a / 2) + a % 2; }
  const law::ConeLaw& law_of(int triangle) const { return cell_fused[mesh.cell[triangle]] ? law.debonded : law.bonded; }
  bool exact() const { return law.cell != nullptr; }
  bool per_cell() const { return scene.bond_unit == StructureScene::BondUnit::cell; }
  const std::vector<law::CellHistory>& unit_history() const { return per_cell() ? cell_history : history; }
  // The mean strain over cell c at u (its points' weights).
  Eigen::Vector3d cell_strain(int c) const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double weight = 0;
    for (int t : cell_triangles[c])
      for (const Point& p : points[t]) sum += p.weight * strain_at(u, t, p), weight += p.weight;
    return sum / weight;
  }
  Eigen::Vector3d strain_at(const Eigen::VectorXd& x, int t, const Point& p) const {
    Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 12, 1> ue(2 * per);
    for (int a = 0; a < 2 * per; ++a) ue(a) = x(dof(t, a));
    return p.grad_s * ue;
  }

  void setup();
  // The steps of setup: the law refused when unusable; quadrature, constraints, loads at factor
  // 1 and the tangent's pattern.
  void check_law() const;
  void set_quadrature();
  void set_constraints();
  void set_loads();
  void set_pattern();
  // state[i] of every point at x (OpenMP over points: with the exact law each is a small QP).
  // The exact law treats the bonds as `trial_bonds` says; a failed QP makes the energy NaN.
  void evaluate_points(const Eigen::VectorXd& x);
  // Exact law, at u: every unit's debond cascade at its strain (a point's, or a cell's mean); the
  // units where a bond broke (a cell's points then take its bonds).
  int break_bonds();
  void note_failure(const law::CellResponse& r) {
#pragma omp critical(dualcell_structure_failure)
    {
      point_failed = true;
      point_failure = r.message;
    }
  }
  // Π(u), and with `with_tangent` also r_full = f_int − factor·f and K.
  double energy(const Eigen::VectorXd& x, double factor, bool with_gradient, bool with_tangent);
  void newton(double factor, StepResult& out);
  // The area average of the stress over each cell, at u.
  std::vector<Eigen::Vector3d> cell_average_stress() const;
};

}  // namespace dualcell::structure
