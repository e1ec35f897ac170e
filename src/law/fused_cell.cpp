#include "law/fused_cell.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "law/bond.hpp"

namespace dualcell::law {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// The onset φ(N) = max_k g_k·N over the facets' rows (−inf without any).
double onset_measure_of(const Eigen::MatrixXd& facets, const Eigen::VectorXd& N) {
  return facets.rows() > 0 ? (facets * N).maxCoeff() : -inf;
}

// Whether x is a convex combination of the columns of P and the origin (x = Pλ, λ ≥ 0, Σλ ≤ 1),
// to `tolerance` in the units of x: phase one of the simplex method on the n + 1 equality rows
// (the last one Σλ + s = 1 with its slack s), an artificial variable per row, Bland's rule (no
// cycling). A few pivots: n + 1 ≤ 5 rows.
bool in_hull_with_origin(const Eigen::MatrixXd& P, const Eigen::VectorXd& x, double tolerance) {
  const int n = static_cast<int>(P.rows()), k = static_cast<int>(P.cols()), rows = n + 1;
  const int cols = k + 1 + rows;  // λ, s, artificials; then the right-hand side
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(rows, cols + 1);
  T.topLeftCorner(n, k) = P;
  T.block(n, 0, 1, k).setOnes();
  T(n, k) = 1;
  T.col(cols).head(n) = x;
  T(n, cols) = 1;
  for (int i = 0; i < rows; ++i) {
    if (T(i, cols) < 0) T.row(i) *= -1;
    T(i, k + 1 + i) = 1;
  }
  std::vector<int> basis(static_cast<std::size_t>(rows));
  for (int i = 0; i < rows; ++i) basis[static_cast<std::size_t>(i)] = k + 1 + i;
  const double pivot_floor = 1e-12;
  for (int iteration = 0; iteration < 50 * cols; ++iteration) {
    // Reduced costs of minimising the artificials' sum: minus the column's sum over the rows
    // whose basic variable is artificial.
    int entering = -1;
    for (int j = 0; j < k + 1 && entering < 0; ++j) {
      double cost = 0;
      for (int i = 0; i < rows; ++i)
        if (basis[static_cast<std::size_t>(i)] > k) cost -= T(i, j);
      if (cost < -pivot_floor) entering = j;
    }
    if (entering < 0) break;
    int leaving = -1;
    double ratio = inf;
    for (int i = 0; i < rows; ++i) {
      if (T(i, entering) <= pivot_floor) continue;
      const double r = T(i, cols) / T(i, entering);
      if (r < ratio || (r == ratio && basis[static_cast<std::size_t>(i)] < basis[static_cast<std::size_t>(leaving)]))
        ratio = r, leaving = i;
    }
    if (leaving < 0) break;  // cannot happen while the artificials bound the sum
    T.row(leaving) /= T(leaving, entering);
    for (int i = 0; i < rows; ++i)
      if (i != leaving) T.row(i) -= T(i, entering) * T.row(leaving);
    basis[static_cast<std::size_t>(leaving)] = entering;
  }
  double infeasibility = 0;
  for (int i = 0; i < rows; ++i)
    if (basis[static_cast<std::size_t>(i)] > k) infeasibility += T(i, cols);
  return infeasibility <= tolerance;
}

}  // namespace

CondensedCell debonded_cell(const CondensedCell& cell) {
  CondensedCell out = cell;
  out.lower_bonded = cell.lower_broken;
  out.upper_bonded = cell.upper_broken;
  std::fill(out.bonded.begin(), out.bonded.end(), std::uint8_t{0});
  return out;
}

BondedCell bonded_cell(const CondensedCell& cell) {
  const int n = cell.n_macro, L = cell.longitudinal;
  CellEvaluator evaluator(cell);
  BondedCell out;
  out.S.resize(n, n);
  Eigen::MatrixXd A(cell.n_rows(), n + L);  // bond forces per unit macro stress (and per unit ε33)
  for (int j = 0; j < n; ++j) {
    Eigen::Vector3d N = Eigen::Vector3d::Zero();
    N(j) = 1;
    const double s = evaluator.bonded_load(N);
    CellHistory history = evaluator.unloaded();
    const CellResponse r = evaluator.at_stress(s * N, history);
    if (!r.ok || r.broken > 0)
      throw std::invalid_argument("the bonded cell's response to unit stress " + std::to_string(j) +
                                  (r.ok ? " breaks a bond below its onset" : " failed: " + r.message));
    out.S.col(j) = r.strain.head(n) / s;
    A.col(j) = r.forces / s;
  }
  out.S = 0.5 * (out.S + out.S.transpose());
  if (L == 1) {
    // σ̄ = 0 and a strain along the fibres small enough that no bond breaks (linear below the
    // onset, so its size does not matter): 1e-6 and smaller until none does.
    double e = 1e-6;
    CellResponse r;
    for (int tries = 0; tries < 10; ++tries, e /= 16) {
      CellHistory history = evaluator.unloaded();
      r = evaluator.at(MacroState::stress(Eigen::Vector3d::Zero()).hold(MacroState::zz, e), history);
      if (!r.ok || r.broken == 0) break;
    }
    if (!r.ok || r.broken > 0)
      throw std::invalid_argument(std::string("the bonded cell's response to a strain along the fibres ") +
                                  (r.ok ? "breaks a bond at " + std::to_string(16 * e) : "failed: " + r.message));
    out.A33 = r.strain.head(n) / e;
    out.C33 = r.stress_zz / e;
    A.col(n) = r.forces / e;
  }
  // Each finite strength bound of a bonded row is a facet: a_r·s = bound.
  std::vector<Eigen::VectorXd> facets;
  for (int r = 0; r < cell.n_rows(); ++r) {
    if (!cell.bonded[static_cast<std::size_t>(cell.pair[static_cast<std::size_t>(r)])]) continue;
    for (const double bound : {cell.lower_bonded(r), cell.upper_bonded(r)})
      if (std::isfinite(bound) && bound != 0) facets.push_back(A.row(r).transpose() / bound);
  }
  out.facets.resize(static_cast<Eigen::Index>(facets.size()), n + L);
  for (std::size_t k = 0; k < facets.size(); ++k) out.facets.row(static_cast<Eigen::Index>(k)) = facets[k].transpose();
  if (cell.shear == 2 && cell.shear_rows > 0) {
    // The shear along the fibres with every tie held: τ = Dz Γ and the rows' forces q = Q Γ.
    Eigen::MatrixXd Q(cell.shear_rows, 2);
    for (int j = 0; j < 2; ++j) {
      CellHistory lifted = evaluator.unloaded();
      const CellResponse r = evaluator.at(
          MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(Eigen::Vector2d::Unit(j)), lifted, BondMode::lifted);
      if (!r.ok) throw std::invalid_argument("the bonded cell's shear along the fibres failed: " + r.message);
      out.Dz.col(j) = r.shear_z;
      Q.col(j) = r.forces_z;
    }
    out.Dz = 0.5 * (out.Dz + out.Dz.transpose());
    std::vector<Eigen::Vector2d> along;
    for (int q = 0; q < cell.shear_rows; ++q) {
      const double bound = cell.strength_z(q);
      if (!cell.bonded[static_cast<std::size_t>(cell.pair_z[static_cast<std::size_t>(q)])] || !std::isfinite(bound) ||
          bound == 0)
        continue;
      along.push_back(Q.row(q).transpose() / bound);
      along.push_back(-Q.row(q).transpose() / bound);
    }
    out.facets_z.resize(static_cast<Eigen::Index>(along.size()), 2);
    for (std::size_t k = 0; k < along.size(); ++k)
      out.facets_z.row(static_cast<Eigen::Index>(k)) = along[k].transpose();
  }
  return out;
}

namespace {

// The facets on the onset polytope: g_k is one of its facets unless it lies in the convex hull
// of the origin and the other facets (then g_k·s ≤ max(0, max_j g_j·s) for every s: another
// bond always reaches its strength first). Repeats are dropped first (one of two equal facets
// stays). The rows of `all` kept, in order.
std::vector<int> polytope_facets(const Eigen::MatrixXd& all) {
  const int count = static_cast<int>(all.rows()), n = static_cast<int>(all.cols());
  const double scale = count > 0 ? all.rowwise().norm().maxCoeff() : 1.0;
  std::vector<int> distinct;
  for (int k = 0; k < count; ++k) {
    bool repeat = all.row(k).norm() <= facet_tolerance * scale;
    for (int j : distinct)
      if (!repeat && (all.row(k) - all.row(j)).norm() <= facet_tolerance * scale) repeat = true;
    if (!repeat) distinct.push_back(k);
  }
  std::vector<int> rows;
  for (std::size_t a = 0; a < distinct.size(); ++a) {
    Eigen::MatrixXd others(n, static_cast<Eigen::Index>(distinct.size()) - 1);
    for (std::size_t b = 0, c = 0; b < distinct.size(); ++b)
      if (b != a) others.col(static_cast<Eigen::Index>(c++)) = all.row(distinct[b]).transpose() / scale;
    if (!in_hull_with_origin(others, all.row(distinct[a]).transpose() / scale, facet_tolerance))
      rows.push_back(distinct[a]);
  }
  return rows;
}

// The kept facets' onset against every bound's, the largest relative difference over directions
// of the load: the sphere of (σxx, σyy, √2σxy) or the circle (sample_directions) for the plane's
// facets and for the shear's two components; for (σ̄, ε33) directions drawn from a fixed seed in
// the facets' own scale (each column divided by its largest entry), so that ε33 (per unit strain)
// and σ̄ (per unit stress) both matter.
double onset_error(const Eigen::MatrixXd& all, const Eigen::MatrixXd& kept) {
  const int n = static_cast<int>(all.cols());
  std::vector<Eigen::VectorXd> directions;
  if (n <= 3) {
    for (const Eigen::Vector3d& d : sample_directions(n == 3 ? 3 : 2, onset_check_directions))
      directions.emplace_back(d.head(n));
  } else {
    // A column that loads no bond (all 0) keeps its scale 1.
    const Eigen::VectorXd scale =
        all.cwiseAbs().colwise().maxCoeff().transpose().unaryExpr([](double v) { return v > 0 ? v : 1.0; });
    std::mt19937_64 generator(4);
    const auto uniform = [&] { return (static_cast<double>(generator() >> 11) + 0.5) * 0x1.0p-53; };
    for (int i = 0; i < onset_check_directions; ++i) {
      Eigen::VectorXd d(n);
      for (int k = 0; k < n; ++k) d(k) = 2 * uniform() - 1;
      directions.push_back(d.cwiseQuotient(scale));
    }
  }
  double error = 0;
  for (const Eigen::VectorXd& N : directions) {
    const double every = onset_measure_of(all, N), at_kept = onset_measure_of(kept, N);
    if (every > 0) error = std::max(error, std::abs(at_kept / every - 1));
  }
  return error;
}

// H_bb = Q R⁻ᵀ Δ R⁻¹ Qᵀ + c (I − QQᵀ) with G = QR (fused_cell.hpp): GᵀH_bb G = Δ, so that the
// rows with right-hand side H_bb G s carry p = G s and give back Δ s; throws where G does not
// span its load.
Eigen::MatrixXd facet_flexibility(const Eigen::MatrixXd& G, const Eigen::MatrixXd& Delta) {
  const int F = static_cast<int>(G.rows()), n = static_cast<int>(G.cols());
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(G);
  const Eigen::VectorXd R_diagonal =
      F >= n ? Eigen::VectorXd(qr.matrixQR().diagonal().cwiseAbs()) : Eigen::VectorXd::Zero(1);
  if (F < n || R_diagonal.minCoeff() <= 1e-12 * R_diagonal.maxCoeff())
    throw std::invalid_argument(
        "the onset facets do not span the macro load: the onset is unbounded along some "
        "direction and the bonded cell cannot carry a fuse there");
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(F, n);
  const Eigen::MatrixXd R = Eigen::MatrixXd(qr.matrixQR()).topRows(n).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd Rinv = R.inverse();
  const Eigen::MatrixXd core = Rinv.transpose() * Delta * Rinv;
  Eigen::MatrixXd H = Q * core * Q.transpose();
  H += core.diagonal().maxCoeff() * (Eigen::MatrixXd::Identity(F, F) - Q * Q.transpose());
  return 0.5 * (H + H.transpose());
}

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& all, const std::vector<int>& rows) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), all.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = all.row(rows[k]);
  return out;
}

}  // namespace

FusedCell cell_with_fuse(const CondensedCell& cell, const CondensedCell& after) {
  // The strain along the fibres where both carry it (a cell on the symmetry boundary has ε33 but
  // no shear, and its small cell stays in the plane).
  const int n = cell.n_macro, L = cell.longitudinal == 1 && after.longitudinal == 1 ? 1 : 0;
  if (!cell.adhesion()) throw std::invalid_argument("the cell has no adhesion: it has no fuse");
  if (after.adhesion() || after.n_macro != n || after.volume != cell.volume || !(after.S0 - cell.S0).isZero(0))
    throw std::invalid_argument("the cell past the fuse is not a cell of contact rows with the cell's macro part");
  if (L == 1 && (after.longitudinal != 1 || after.A33 != cell.A33 || after.C33 != cell.C33))
    throw std::invalid_argument("the cell past the fuse does not carry the cell's open response along the fibres");
  CondensedCell in_plane;  // the cell without its ε33 column, where `after` has none
  if (L != cell.longitudinal) {
    in_plane = cell;
    in_plane.longitudinal = 0;
    in_plane.A33.resize(0, 0), in_plane.C33.resize(0, 0), in_plane.y33.resize(0, 0);
    in_plane.CT.resize(0, in_plane.CT.cols());  // σ33 per kelvin: none without ε33
  }
  const BondedCell bonded = bonded_cell(L != cell.longitudinal ? in_plane : cell);
  FusedCell out;
  out.candidate_facets = static_cast<int>(bonded.facets.rows());
  const std::vector<int> rows = polytope_facets(bonded.facets);
  const int F = static_cast<int>(rows.size());
  out.facets = F;
  const Eigen::MatrixXd G = rows_of(bonded.facets, rows);
  out.onset_error = onset_error(bonded.facets, G);

  // Δ = |Ω| (S₀ − S_b), with ε33 the 4 × 4 [S₀ − S_b, A33 − A33_b; ·, C33_b − C33] (the bonded rows
  // carry p = G s with s = (σ̄, ε33): ε̄ gains −Y_bᵀp/|Ω| and σ33 y33_b·p/|Ω|, docs/method.md §16d).
  Eigen::MatrixXd Delta(n + L, n + L);
  Delta.topLeftCorner(n, n) = cell.S0 - bonded.S;
  if (L == 1) {
    Delta.topRightCorner(n, 1) = cell.A33 - bonded.A33;
    Delta.bottomLeftCorner(1, n) = (cell.A33 - bonded.A33).transpose();
    Delta(n, n) = bonded.C33 - cell.C33(0, 0);
  }
  Delta *= cell.volume;
  const Eigen::MatrixXd Hbb = facet_flexibility(G, Delta);
  const Eigen::MatrixXd Yb = Hbb * G.leftCols(n);
  const Eigen::MatrixXd Yc = after.Y;
  const int m = after.n_rows();
  const Eigen::MatrixXd Hbc = Yb * (cell.volume * cell.S0).llt().solve(Yc.transpose());

  CondensedCell& c = out.cell;
  c.n_macro = n;
  c.volume = cell.volume;
  c.S0 = cell.S0;
  c.Y.resize(F + m, n);
  c.Y << Yb, Yc;
  c.H.resize(F + m, F + m);
  c.H << Hbb, Hbc, Hbc.transpose(), after.H;
  c.G.resize(after.G.rows(), F + m);  // the equality rows of `after` (none for a small cell)
  c.G << Eigen::MatrixXd::Zero(after.G.rows(), F), after.G;
  c.tangential.assign(static_cast<std::size_t>(F), 1);
  c.tangential.insert(c.tangential.end(), after.tangential.begin(), after.tangential.end());
  c.pair.assign(static_cast<std::size_t>(F + m), 0);
  c.n_pairs = 1;
  c.bonded = {1};
  c.lower_bonded.resize(F + m);
  c.upper_bonded.resize(F + m);
  c.lower_broken.resize(F + m);
  c.upper_broken.resize(F + m);
  // The facet rows by the bond rule; the rows of `after` carry nothing while the facets hold
  // (their pair is the fuse's, bonded) and their own broken bounds past it.
  const bond::Bounds facet_intact = bond::bounds(bond::Kind::facet, bond::State::intact, 0, 0, 0);
  const bond::Bounds facet_broken = bond::bounds(bond::Kind::facet, bond::State::broken, 0, 0, 0);
  c.lower_bonded << Eigen::VectorXd::Constant(F, facet_intact.lower), Eigen::VectorXd::Zero(m);
  c.upper_bonded << Eigen::VectorXd::Constant(F, facet_intact.upper), Eigen::VectorXd::Zero(m);
  c.lower_broken << Eigen::VectorXd::Constant(F, facet_broken.lower), after.lower_broken;
  c.upper_broken << Eigen::VectorXd::Constant(F, facet_broken.upper), after.upper_broken;
  if (L == 1) {
    c.longitudinal = 1;
    c.A33 = cell.A33;
    c.C33 = cell.C33;
    c.y33.resize(F + m, 1);
    c.y33 << Hbb * G.col(n), after.y33;
  }
  if (cell.shear == 2) {
    // Past the fuse the pair is broken: τ = D0z Γ, the open cell's. Bonded, facet rows of the
    // same pair carry q = G_z Γ (|q_k| ≤ 1: row k at its strength exactly on facet k).
    c.shear = 2;
    c.D0z = cell.D0z;
    if (bonded.facets_z.rows() > 0) {
      out.candidate_facets_z = static_cast<int>(bonded.facets_z.rows());
      const std::vector<int> rows_z = polytope_facets(bonded.facets_z);
      const int Fz = static_cast<int>(rows_z.size());
      out.facets_z = Fz;
      const Eigen::MatrixXd Gf = rows_of(bonded.facets_z, rows_z);
      out.onset_error = std::max(out.onset_error, onset_error(bonded.facets_z, Gf));
      const Eigen::MatrixXd Hz = facet_flexibility(Gf, cell.volume * (bonded.Dz - cell.D0z));
      c.shear_rows = Fz;
      c.Yz = Hz * Gf;
      c.Hz = Hz;
      c.Gz.resize(0, Fz);
      // A facet's strength is 1 by its normalisation, both ways along z (the rule's facet row).
      c.strength_z = Eigen::VectorXd::Constant(Fz, bond::bounds(bond::Kind::facet, bond::State::intact, 0, 0, 0).upper);
      c.pair_z.assign(static_cast<std::size_t>(Fz), 0);
    }
  }
  return out;
}

ConeCheck check_along_fuse_paths(const CondensedCell& fused, const CellSample& past_fuse) {
  CellEvaluator evaluator(fused);
  // A direction's error: the largest along its path, each point from the intact cell on.
  return check_over(past_fuse, [&](std::size_t i) {
    CellHistory history = evaluator.unloaded();
    double error = 0;
    const auto at = [&](const Eigen::Vector3d& strain, const Eigen::Vector3d& stress) {
      const CellResponse r = evaluator.at_strain(strain, history);
      const double e = r.ok ? (r.stress - stress).norm() / stress.norm() : inf;
      error = std::max(error, std::isfinite(e) ? e : inf);
    };
    for (std::size_t k = 0; k < past_fuse.path_strain[i].size(); ++k)
      at(past_fuse.path_strain[i][k], past_fuse.path_stress[i][k]);
    at(past_fuse.strain[i], past_fuse.stress[i]);
    return error;
  });
}

}  // namespace dualcell::law
