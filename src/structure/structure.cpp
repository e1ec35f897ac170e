#include "structure/structure.hpp"

#include <omp.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.hpp"
#include "fem/edge_conditions.hpp"
#include "fem/element.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace dualcell::structure {

int StructureMesh::node_at(const Eigen::Vector2d& x) const {
  const double size = std::max((nodes.colwise().maxCoeff() - nodes.colwise().minCoeff()).maxCoeff(), 1e-300);
  return fem::node_near(
      static_cast<int>(nodes.rows()), [&](int i) { return Eigen::Vector2d(nodes.row(i).transpose()); }, x, size);
}

StructureMesh build_structure_mesh(const StructureScene& scene) {
  const int q = element_order(scene.element), m = scene.elements_per_cell;
  const int squares_x = scene.nx * m, squares_y = scene.ny * m;
  const int Nx = q * squares_x + 1, Ny = q * squares_y + 1;
  const double h = scene.cell_size / (m * q);
  StructureMesh mesh;
  mesh.nodes.resize(static_cast<Eigen::Index>(Nx) * Ny, 2);
  for (int j = 0; j < Ny; ++j)
    for (int i = 0; i < Nx; ++i) mesh.nodes.row(i + Nx * j) << i * h, j * h;
  const auto id = [&](int i, int j) { return i + Nx * j; };
  const int per = q == 1 ? 3 : 6;
  mesh.triangles.resize(2 * squares_x * squares_y, per);
  int t = 0;
  for (int sy = 0; sy < squares_y; ++sy)
    for (int sx = 0; sx < squares_x; ++sx) {
      const int i0 = q * sx, j0 = q * sy;
      // Two counter-clockwise triangles split by the diagonal (0,0)–(1,1), in grid steps of q.
      const std::array<std::array<int, 2>, 3> corners[2] = {{{{0, 0}, {1, 0}, {1, 1}}}, {{{0, 0}, {1, 1}, {0, 1}}}};
      for (const auto& c : corners) {
        for (int k = 0; k < 3; ++k) mesh.triangles(t, k) = id(i0 + q * c[k][0], j0 + q * c[k][1]);
        if (q == 2)
          for (int k = 0; k < 3; ++k) {
            const auto& a = c[k];
            const auto& b = c[(k + 1) % 3];
            mesh.triangles(t, 3 + k) = id(i0 + a[0] + b[0], j0 + a[1] + b[1]);
          }
        mesh.cell.push_back(sx / m + scene.nx * (sy / m));
        ++t;
      }
    }
  for (int j = 0; j < Ny; ++j) mesh.edge_nodes[0].push_back(id(0, j)), mesh.edge_nodes[1].push_back(id(Nx - 1, j));
  for (int i = 0; i < Nx; ++i) mesh.edge_nodes[2].push_back(id(i, 0)), mesh.edge_nodes[3].push_back(id(i, Ny - 1));
  return mesh;
}

namespace {

// One quadrature point of an element: its strain-displacement matrix and weight (w·det J).
struct Point {
  Eigen::MatrixXd grad_s;  // ∇ˢ: the strain-displacement matrix, ε = ∇ˢ u_e (docs/method.md §3)
  double weight;
};

}  // namespace

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
  int threads = 1;                            // the exact law's evaluators: one per OpenMP thread
  law::Bonds trial_bonds = law::Bonds::held;  // what a Newton iterate does with the bonds
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

std::vector<Eigen::Vector3d> HomogenisedStructure::Impl::cell_average_stress() const {
  std::vector<Eigen::Vector3d> cell_stress(cell_fused.size(), Eigen::Vector3d::Zero());
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (std::size_t k = 0; k < points[t].size(); ++k)
      cell_stress[mesh.cell[t]] += points[t][k].weight * state[first_point[t] + k].stress;
  for (auto& s : cell_stress) s /= scene.cell_size * scene.cell_size;
  return cell_stress;
}

void HomogenisedStructure::Impl::evaluate_points(const Eigen::VectorXd& x) {
  const int T = static_cast<int>(mesh.triangles.rows());
#pragma omp parallel for schedule(static) num_threads(threads) if (exact())
  for (int t = 0; t < T; ++t)
    for (std::size_t k = 0; k < points[t].size(); ++k) {
      const int i = first_point[t] + static_cast<int>(k);
      const Eigen::Vector3d strain = strain_at(x, t, points[t][k]);
      if (!exact()) {
        state[i] = law::evaluate(law_of(t), strain);
        continue;
      }
      law::CellResponse r = evaluators[omp_get_thread_num()]->at_strain(strain, history[i], trial_bonds);
      law::ConeState& s = state[i];
      if (!r.ok) {
        s.energy = std::numeric_limits<double>::quiet_NaN();
        note_failure(r);
        continue;
      }
      s.stress = r.stress;
      s.tangent = r.tangent;
      s.energy = r.energy;
      strength_use[i] = r.strength_use;
      s.open = 0;
      for (int row = 0; row < law.cell->n_rows(); ++row) s.open += !law.cell->tangential[row] && r.forces(row) == 0;
    }
}

int HomogenisedStructure::Impl::break_bonds() {
  int broke = 0;
  if (per_cell()) {
    const int C = static_cast<int>(cell_history.size());
#pragma omp parallel for schedule(static) num_threads(threads) reduction(+ : broke)
    for (int c = 0; c < C; ++c) {
      const law::CellResponse r =
          evaluators[omp_get_thread_num()]->at_strain(cell_strain(c), cell_history[c], law::Bonds::cascade);
      if (!r.ok) note_failure(r);
      if (!r.ok || r.newly_broken == 0) continue;
      ++broke;
      for (int t : cell_triangles[c])
        for (int i = first_point[t]; i < first_point[t + 1]; ++i) history[i].bonded = cell_history[c].bonded;
    }
    return broke;
  }
  const int T = static_cast<int>(mesh.triangles.rows());
#pragma omp parallel for schedule(static) num_threads(threads) reduction(+ : broke)
  for (int t = 0; t < T; ++t)
    for (std::size_t k = 0; k < points[t].size(); ++k) {
      const int i = first_point[t] + static_cast<int>(k);
      const law::CellResponse r =
          evaluators[omp_get_thread_num()]->at_strain(strain_at(u, t, points[t][k]), history[i], law::Bonds::cascade);
      if (!r.ok) note_failure(r);
      broke += r.ok && r.newly_broken > 0;
    }
  return broke;
}

double HomogenisedStructure::first_fuse_factor() {
  Impl& s = *impl_;
  if (!s.exact() && !s.law.onset.linear) return std::numeric_limits<double>::infinity();
  if (s.exact() && !s.law.cell->adhesion()) return std::numeric_limits<double>::infinity();
  // From the unloaded, unfused state: the bonded response to t·(loads, prescribed values) is t
  // times the response at t = 1 (W is positively homogeneous of degree 2; the exact law with its
  // strengths lifted too), and so is every cell's average stress and every point's bond force,
  // while φ and the strength use are positively homogeneous of degree 1.
  const Eigen::VectorXd u_kept = s.u;
  const std::vector<std::uint8_t> fused_kept = s.cell_fused;
  const std::vector<law::CellHistory> history_kept = s.history, cell_history_kept = s.cell_history;
  std::fill(s.cell_fused.begin(), s.cell_fused.end(), 0);
  if (s.exact()) {
    for (auto& h : s.history) h = s.evaluators[0]->unloaded();
    for (auto& h : s.cell_history) h = s.evaluators[0]->unloaded();
  }
  s.trial_bonds = law::Bonds::lifted;
  s.u.setZero();
  StepResult probe;
  s.newton(1.0, probe);
  s.trial_bonds = law::Bonds::held;
  double phi = 0;
  if (!s.exact()) {
    for (const Eigen::Vector3d& sigma : s.cell_average_stress())
      phi = std::max(phi, law::onset_measure(s.law.onset, sigma));
  } else if (s.per_cell()) {
    for (std::size_t c = 0; c < s.cell_history.size(); ++c) {
      law::CellHistory h = s.evaluators[0]->unloaded();
      phi = std::max(
          phi, s.evaluators[0]->at_strain(s.cell_strain(static_cast<int>(c)), h, law::Bonds::lifted).strength_use);
    }
  } else {
    for (std::size_t i = 0; i < s.history.size(); ++i) phi = std::max(phi, s.strength_use[i]);
  }
  s.u = u_kept;
  s.cell_fused = fused_kept;
  s.history = history_kept;
  s.cell_history = cell_history_kept;
  if (!probe.converged) return std::numeric_limits<double>::quiet_NaN();
  return phi > 0 ? 1 / phi : std::numeric_limits<double>::infinity();
}

HomogenisedStructure::HomogenisedStructure(const StructureScene& scene, const CellLaw& law)
    : impl_(std::make_unique<Impl>()) {
  impl_->scene = scene;
  impl_->law = law;
  impl_->setup();
}

HomogenisedStructure::~HomogenisedStructure() = default;

const StructureMesh& HomogenisedStructure::mesh() const { return impl_->mesh; }
const std::vector<std::uint8_t>& HomogenisedStructure::fused_cells() const { return impl_->cell_fused; }

int HomogenisedStructure::broken_units() const {
  const Impl& s = *impl_;
  int count = 0;
  for (const law::CellHistory& h : s.unit_history())
    for (std::size_t pair = 0; pair < h.bonded.size(); ++pair)
      if (s.law.cell->bonded[pair] && !h.bonded[pair]) {
        ++count;
        break;
      }
  return count;
}

int HomogenisedStructure::n_units() const {
  return impl_->per_cell() ? static_cast<int>(impl_->cell_fused.size()) : impl_->first_point.back();
}

void HomogenisedStructure::Impl::check_law() const {
  if (exact()) {
    const std::string problem = law::consistency_problem(*law.cell);
    if (!problem.empty()) throw InputError("the exact cell law is not usable: " + problem);
    if (law.cell->n_macro != 3)
      throw InputError(
          "the exact cell law has no shear (its cell has the symmetry boundary): a structure needs all three "
          "stresses; use the cone-wise law or a periodic or uniform cell");
  } else {
    for (const auto* l : {&law.bonded, &law.debonded}) {
      const std::string problem = law::admissibility_problem(*l);
      if (!problem.empty()) throw InputError("the cell law is not admissible: " + problem);
    }
  }
}

// Quadrature: per triangle its points, centroid matrix and area; the points' state and, with
// the exact law, their histories and the evaluators.
void HomogenisedStructure::Impl::set_quadrature() {
  const Eigen::Index T = mesh.triangles.rows();
  // p1 constant strain, one point; p2 the 6-point degree-4 rule.
  points.resize(T);
  grad_s_centroid.resize(T);
  area.resize(T);
  std::vector<Eigen::Vector2d> x(per);
  for (Eigen::Index t = 0; t < T; ++t) {
    for (int k = 0; k < per; ++k) x[k] = mesh.nodes.row(mesh.triangles(t, k)).transpose();
    double det_J = 0;
    grad_s_centroid[t] = fem::strain_displacement_at(x, 1.0 / 3, 1.0 / 3, det_J);
    if (per == 3) {
      points[t].push_back({grad_s_centroid[t], 0.5 * det_J});
    } else {
      for (const auto& p : fem::triangle_rule()) {
        Eigen::MatrixXd grad_s = fem::strain_displacement_at(x, p.L1, p.L2, det_J);
        points[t].push_back({std::move(grad_s), p.weight * det_J});
      }
    }
    area[t] = fem::element_area(x);
  }
  cell_triangles.assign(cell_fused.size(), {});
  for (Eigen::Index t = 0; t < T; ++t) cell_triangles[mesh.cell[t]].push_back(static_cast<int>(t));
  first_point.assign(T + 1, 0);
  for (Eigen::Index t = 0; t < T; ++t) first_point[t + 1] = first_point[t] + static_cast<int>(points[t].size());
  const int n_points = first_point[T];
  state.assign(n_points, law::ConeState{});
  if (exact()) {
    threads = omp_get_max_threads();
    for (int k = 0; k < threads; ++k) evaluators.push_back(std::make_unique<law::CellEvaluator>(*law.cell));
    history.assign(n_points, evaluators[0]->unloaded());
    if (per_cell()) cell_history.assign(cell_fused.size(), evaluators[0]->unloaded());
    strength_use.assign(n_points, 0.0);
  }
}

void HomogenisedStructure::Impl::set_constraints() {
  // Constraints: edges (fixed, roller, displacement), then point supports (fem::held_components).
  constrained_by.assign(n_dofs, -1);
  prescribed = Eigen::VectorXd::Zero(n_dofs);
  const auto held = fem::held_components(scene, mesh.edge_nodes, [&](const Support& s) {
    const int node = mesh.node_at(s.at);
    if (node < 0)
      throw InputError(position_text(s.where, "support", s.at) +
                       ": no node there (nodes lie on a grid of step cell_size/(elements_per_cell·order))");
    return node;
  });
  for (const fem::HeldComponent& h : held) {
    constrained_by[2 * h.point + h.component] = h.by;
    prescribed(2 * h.point + h.component) = h.value;
  }
  free_index.assign(n_dofs, -1);
  n_free = 0;
  for (int d = 0; d < n_dofs; ++d)
    if (constrained_by[d] < 0) free_index[d] = n_free++;
}

void HomogenisedStructure::Impl::set_loads() {
  // Loads at factor 1: edge tractions (linear from start to end, fem::add_edge_traction per
  // element edge, q + 1 nodes each), point loads.
  f = Eigen::VectorXd::Zero(n_dofs);
  const int q = per == 3 ? 1 : 2;
  for (int e = 0; e < 4; ++e) {
    const EdgeCondition& c = scene.edges[e];
    if (c.kind != EdgeKind::traction) continue;
    const auto& nodes = mesh.edge_nodes[e];
    const Eigen::Vector2d start = mesh.nodes.row(nodes.front()).transpose();
    const double length = (mesh.nodes.row(nodes.back()).transpose() - start).norm();
    const auto traction = [&](int node) {
      const double position = (mesh.nodes.row(node).transpose() - start).norm() / length;
      return (c.traction_start + position * (c.traction_end - c.traction_start)).eval();
    };
    for (std::size_t k = 0; k + q < nodes.size(); k += q) {
      const int a = nodes[k], b = nodes[k + q];
      const int ids[3] = {a, b, q == 2 ? nodes[k + 1] : -1};
      const Eigen::Vector2d x[3] = {
          mesh.nodes.row(a).transpose(), mesh.nodes.row(b).transpose(),
          q == 2 ? Eigen::Vector2d(mesh.nodes.row(nodes[k + 1]).transpose()) : Eigen::Vector2d::Zero()};
      fem::add_edge_traction(std::span<const Eigen::Vector2d>(x, q + 1), std::span<const int>(ids, q + 1), traction(a),
                             traction(b), f);
    }
  }
  for (const PointLoad& p : scene.point_loads) {
    const int node = mesh.node_at(p.at);
    if (node < 0)
      throw InputError(position_text(p.where, "point load", p.at) +
                       ": no node there (nodes lie on a grid of step cell_size/(elements_per_cell·order))");
    f.segment<2>(2 * node) += p.force;
  }
}

void HomogenisedStructure::Impl::set_pattern() {
  const Eigen::Index T = mesh.triangles.rows();
  // The tangent's pattern, once.
  std::vector<Eigen::Triplet<double, int>> entries;
  for (Eigen::Index t = 0; t < T; ++t)
    for (int a = 0; a < 2 * per; ++a)
      for (int b = 0; b <= a; ++b) {
        int i = free_index[dof(static_cast<int>(t), a)], j = free_index[dof(static_cast<int>(t), b)];
        if (i < 0 || j < 0) continue;
        if (i < j) std::swap(i, j);
        entries.emplace_back(i, j, 0.0);
      }
  K.resize(n_free, n_free);
  K.setFromTriplets(entries.begin(), entries.end());
  K.makeCompressed();
  slot.resize(T);
  for (Eigen::Index t = 0; t < T; ++t) {
    slot[t].assign(2 * per * 2 * per, -1);
    for (int a = 0; a < 2 * per; ++a)
      for (int b = 0; b <= a; ++b) {
        int i = free_index[dof(static_cast<int>(t), a)], j = free_index[dof(static_cast<int>(t), b)];
        if (i < 0 || j < 0) continue;
        if (i < j) std::swap(i, j);
        const int* begin = K.innerIndexPtr() + K.outerIndexPtr()[j];
        const int* end = K.innerIndexPtr() + K.outerIndexPtr()[j + 1];
        slot[t][a * 2 * per + b] = static_cast<int>(std::lower_bound(begin, end, i) - K.innerIndexPtr());
      }
  }
  if (mesh.node_at(scene.watch) < 0)
    throw InputError(position_text(scene.watch_where, "[output] watch", scene.watch) + ": no node there");
  if (n_free > 0) cholesky.analyze(K);
  u = Eigen::VectorXd::Zero(n_dofs);
  r_full.resize(n_dofs);
  f_int.resize(n_dofs);
}

void HomogenisedStructure::Impl::setup() {
  check_law();
  mesh = build_structure_mesh(scene);
  per = static_cast<int>(mesh.triangles.cols());
  const Eigen::Index n_nodes = mesh.nodes.rows();
  n_dofs = 2 * static_cast<int>(n_nodes);
  cell_fused.assign(static_cast<std::size_t>(scene.nx) * scene.ny, 0);

  set_quadrature();
  set_constraints();
  set_loads();
  set_pattern();
}

double HomogenisedStructure::Impl::energy(const Eigen::VectorXd& x, double factor, bool with_gradient,
                                          bool with_tangent) {
  evaluate_points(x);
  double Pi = -factor * f.dot(x);
  if (with_gradient) f_int.setZero();
  if (with_tangent) std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  const int n = 2 * per;
  Eigen::MatrixXd Ke(n, n);
  Eigen::VectorXd fe(n);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    if (with_tangent) Ke.setZero();
    for (std::size_t k = 0; k < points[t].size(); ++k) {
      const Point& p = points[t][k];
      const law::ConeState& s = state[first_point[t] + k];
      Pi += p.weight * s.energy;
      if (with_gradient) {
        fe.noalias() = p.weight * (p.grad_s.transpose() * s.stress);
        for (int a = 0; a < n; ++a) f_int(dof(static_cast<int>(t), a)) += fe(a);
      }
      if (with_tangent) Ke.noalias() += p.weight * (p.grad_s.transpose() * s.tangent * p.grad_s);
    }
    if (with_tangent)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b <= a; ++b) {
          const int k = slot[t][a * n + b];
          if (k >= 0) K.valuePtr()[k] += Ke(a, b);
        }
  }
  if (with_gradient) r_full = f_int - factor * f;
  return Pi;
}

void HomogenisedStructure::Impl::newton(double factor, StepResult& out) {
  Eigen::VectorXd r(n_free), delta(n_free);
  for (int d = 0; d < n_dofs; ++d)
    if (constrained_by[d] >= 0) u(d) = factor * prescribed(d);
  out.converged = false;
  double r_initial = 0;
  for (int iteration = 0; iteration <= scene.max_newton_steps; ++iteration) {
    const double Pi = energy(u, factor, true, true);
    for (int d = 0; d < n_dofs; ++d)
      if (free_index[d] >= 0) r(free_index[d]) = r_full(d);
    // Scale: the larger of the internal and the external forces (their sum is what equilibrium
    // balances), and the residual the step started from: prescribed displacements that a rigid
    // motion satisfies end in a stress-free state where both forces vanish, and only the
    // starting residual says what "small" is there.
    if (iteration == 0) r_initial = r.norm();
    const double scale = std::max({f_int.norm(), factor * f.norm(), r_initial, 1e-300});
    out.residual = r.norm() / scale;
    out.energy = Pi;
    if (progress)
      progress->update([&] {
        char text[200];
        std::snprintf(text, sizeof text, "load factor %g: Newton %d, residual %.1e (tol %.0e), %d fused cells, %s",
                      factor, iteration, out.residual, scene.tolerance, out.newly_fused_cells,
                      seconds_text(progress->seconds()).c_str());
        return std::string(text);
      });
    if (std::isfinite(Pi) && (out.residual <= scene.tolerance || n_free == 0)) {
      out.converged = true;
      return;
    }
    if (iteration == scene.max_newton_steps) break;
    if (cholesky.factorize(K) != linalg::CholeskyStatus::ok)
      throw InputError(
          "the structure's tangent is not positive definite: the edges and supports do not hold it "
          "against every rigid-body motion (give a [[support]] or a fixed, roller or displacement edge)");
    cholesky.solve(-r, delta);
    // Backtracking (Armijo) on Π: the full step is exact once every element's open planes are
    // right. Near the solution the decrease a step promises, t·|rᵀδ|, falls below the round-off
    // of Π itself (Π is a sum of terms of size |fᵀu|, each rounded): Π can no longer tell a good
    // step from a bad one there, and the step is judged by the residual instead (‖r‖ must fall),
    // which Newton's method on the piecewise-linear gradient does once the open sets settle.
    const double slope = r.dot(delta);
    const double noise = 64 * std::numeric_limits<double>::epsilon() * (std::abs(Pi) + std::abs(factor * f.dot(u)));
    const double r_norm = r.norm();
    const auto set_trial = [&](double t) {
      for (int d = 0; d < n_dofs; ++d)
        if (free_index[d] >= 0) trial(d) = u(d) + t * delta(free_index[d]);
    };
    const auto trial_residual = [&] {
      energy(trial, factor, true, false);
      double sum = 0;
      for (int d = 0; d < n_dofs; ++d)
        if (free_index[d] >= 0) sum += r_full(d) * r_full(d);
      return std::sqrt(sum);
    };
    double t = 1;
    trial = u;
    for (;;) {
      set_trial(t);
      if (energy(trial, factor, false, false) <= Pi + 1e-4 * t * slope) break;
      if (-t * slope <= noise) {
        for (t = 1; t >= 1e-12; t /= 2) {
          set_trial(t);
          if (trial_residual() <= (1 - 1e-4 * t) * r_norm) break;
        }
        break;
      }
      if (t < 1e-12) break;
      t /= 2;
    }
    u = trial;
    ++out.newton_steps;
  }
}

void HomogenisedStructure::set_progress(Progress* progress) { impl_->progress = progress; }

StepResult HomogenisedStructure::solve_step(double factor) {
  Impl& s = *impl_;
  StepResult out;
  out.factor = factor;
  s.point_failed = false;
  const double before = s.energy(s.u, factor, false, false);
  for (;;) {
    s.newton(factor, out);
    if (!out.converged) break;
    int fused_now = 0;
    if (s.exact()) {
      // The fuse per point: each point's debond cascade at its converged strain.
      if (!s.law.cell->adhesion()) break;
      fused_now = s.break_bonds();
      out.newly_broken_units += fused_now;
    } else {
      // The fuse: cells whose average stress leaves the onset surface switch, irreversibly.
      if (!s.law.onset.linear) break;
      const std::vector<Eigen::Vector3d> cell_stress = s.cell_average_stress();
      for (std::size_t c = 0; c < s.cell_fused.size(); ++c)
        if (!s.cell_fused[c] && law::onset_measure(s.law.onset, cell_stress[c]) >= 1) {
          s.cell_fused[c] = 1;
          ++fused_now;
        }
      out.newly_fused_cells += fused_now;
    }
    if (fused_now == 0) break;
    if (++out.fuse_rounds > s.scene.max_fuse_rounds) {
      out.converged = false;
      break;
    }
  }
  if (s.point_failed) {
    out.converged = false;
    out.message = "the exact law failed at a quadrature point: " + s.point_failure;
  }
  out.energy_decrease = before - out.energy;

  // The state: displacements, element stresses and open planes (gaps), fuses, reactions.
  s.energy(s.u, factor, true, false);
  out.u = s.u;
  const Eigen::Index T = s.mesh.triangles.rows();
  out.stress.resize(T, 3);
  out.open.resize(T);
  out.fused.resize(T);
  if (s.exact()) out.broken.assign(T, 0.0f);
  for (Eigen::Index t = 0; t < T; ++t) {
    Eigen::Vector3d integral = Eigen::Vector3d::Zero();
    std::uint32_t open = 0;
    int broken = 0;
    for (std::size_t k = 0; k < s.points[t].size(); ++k) {
      const int i = s.first_point[t] + static_cast<int>(k);
      integral += s.points[t][k].weight * s.state[i].stress;
      open = std::max(open, s.state[i].open);
      if (s.exact())
        for (std::size_t pair = 0; pair < s.history[i].bonded.size(); ++pair)
          broken += s.law.cell->bonded[pair] && !s.history[i].bonded[pair];
    }
    out.stress.row(t) = integral.transpose() / s.area[t];
    if (s.exact()) {
      out.open[t] = open;
      out.fused[t] = broken > 0;
      if (s.law.cell->n_pairs > 0)
        out.broken[t] = static_cast<float>(broken) / static_cast<float>(s.law.cell->n_pairs * s.points[t].size());
    } else {
      Eigen::VectorXd ue(2 * s.per);
      for (int a = 0; a < 2 * s.per; ++a) ue(a) = s.u(s.dof(static_cast<int>(t), a));
      out.open[t] = law::evaluate(s.law_of(static_cast<int>(t)), s.grad_s_centroid[t] * ue).open;
      out.fused[t] = s.cell_fused[s.mesh.cell[t]];
    }
    (out.open[t] ? out.open_triangles : out.closed_triangles) += 1;
  }
  for (auto& r : out.reactions) r.setZero();
  for (int d = 0; d < s.n_dofs; ++d)
    if (s.constrained_by[d] >= 0) out.reactions[s.constrained_by[d]](d % 2) += s.r_full(d);
  const int watch = s.mesh.node_at(s.scene.watch);
  if (watch >= 0) out.watch_displacement = s.u.segment<2>(2 * watch);
  return out;
}

}  // namespace dualcell::structure
