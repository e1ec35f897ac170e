// The setup of a structure of homogeneous cells: the law checked against the scene, the
// quadrature points, the held DOFs, the loads and the tangent's fixed pattern.
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
#include "structure/impl.hpp"
#include "structure/structure.hpp"

namespace dualcell::structure {

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
  // p1 constant strain, one point; p2 the 6-point degree-4 rule, or the scene's 3-point one.
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
      const auto add = [&](const fem::TrianglePoint& p) {
        Eigen::MatrixXd grad_s = fem::strain_displacement_at(x, p.L1, p.L2, det_J);
        points[t].push_back({std::move(grad_s), p.weight * det_J});
      };
      if (scene.quadrature == 3)
        for (const auto& p : fem::triangle_rule_3()) add(p);
      else
        for (const auto& p : fem::triangle_rule()) add(p);
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
      return c.traction_at(position);
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

}  // namespace dualcell::structure
