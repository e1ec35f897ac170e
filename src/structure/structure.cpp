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
#include "structure/impl.hpp"

namespace dualcell::structure {

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
          evaluators[omp_get_thread_num()]->at_strain(cell_strain(c), cell_history[c], law::BondMode::cascade);
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
      const law::CellResponse r = evaluators[omp_get_thread_num()]->at_strain(strain_at(u, t, points[t][k]), history[i],
                                                                              law::BondMode::cascade);
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
  s.trial_bonds = law::BondMode::lifted;
  s.u.setZero();
  StepResult probe;
  s.newton(1.0, probe);
  s.trial_bonds = law::BondMode::held;
  double phi = 0;
  if (!s.exact()) {
    for (const Eigen::Vector3d& sigma : s.cell_average_stress())
      phi = std::max(phi, law::onset_measure(s.law.onset, sigma));
  } else if (s.per_cell()) {
    for (std::size_t c = 0; c < s.cell_history.size(); ++c) {
      law::CellHistory h = s.evaluators[0]->unloaded();
      phi = std::max(
          phi, s.evaluators[0]->at_strain(s.cell_strain(static_cast<int>(c)), h, law::BondMode::lifted).strength_use);
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