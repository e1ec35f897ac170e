#include "feti/condense.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "feti/constraints.hpp"
#include "feti/dual.hpp"
#include "feti/macro.hpp"
#include "law/bond.hpp"
#include "law/reduced.hpp"
#include "primal/antiplane.hpp"

namespace dualcell::feti {

namespace {

// A rigid motion's load e (per unit macro stress) at most this fraction of ‖e‖ is round-off of
// the sums R̂ᵀf: the motion is unloaded.
constexpr double load_round_off = 1e-12;
// The elimination of the rows other than the interface solves a nonsingular system to round-off,
// decades below this; a relative residual above it means the system is singular: those rows do
// not hold the cell.
constexpr double elimination_tolerance = 1e-8;

// Rows `rows` and columns `cols` of M.
Eigen::MatrixXd pick(const Eigen::MatrixXd& M, const std::vector<int>& rows, const std::vector<int>& cols) {
  Eigen::MatrixXd out(rows.size(), cols.size());
  for (std::size_t j = 0; j < cols.size(); ++j)
    for (std::size_t i = 0; i < rows.size(); ++i) out(i, j) = M(rows[i], cols[j]);
  return out;
}

std::vector<int> all(Eigen::Index n) {
  std::vector<int> v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = static_cast<int>(i);
  return v;
}

// The load columns beyond the macro stress: a uniform eigen-stress each, held, not a stress
// (docs/theory/model.md §1a). Column n_macro is ε33's when the cell has it, the last ΔT's when it
// has that.
struct Extras {
  bool longitudinal = false, thermal = false;
  int count() const { return int{longitudinal} + int{thermal}; }
  // The uniform part of extra column j (0-based beyond n_macro): ε33 = 1 or ΔT = 1.
  fem::Uniform unit(int j) const { return longitudinal && j == 0 ? fem::Uniform{1.0, 0.0} : fem::Uniform{0.0, 1.0}; }
};

// The macro load per unit stress component k: the load f_k, the dual right-hand sides d_k and
// e_k of §6; beyond them one column per extra (Extras): the load of ε33 = 1 or of ΔT = 1 at
// σ̄ = 0 (its eigen-stress, §3a, §1a; no prescribed displacement scales with it).
struct MacroLoad {
  std::vector<Eigen::VectorXd> f;
  Eigen::MatrixXd D, e;  // columns k
};

MacroLoad macro_load(const FetiSetup& setup, const DualProblem& dual, int n_macro, const Extras& extras) {
  const int n_load = n_macro + extras.count();
  MacroLoad load;
  load.f.resize(n_load);
  load.D.resize(dual.constraints().n_rows(), n_load);
  load.e.resize(dual.G().rows(), n_load);
  for (int k = 0; k < n_load; ++k) {
    const bool extra = k >= n_macro;
    const Eigen::Vector3d unit = extra ? Eigen::Vector3d::Zero() : Eigen::Vector3d::Unit(k).eval();
    load.f[k] = setup.load(unit, extra ? extras.unit(k - n_macro) : fem::Uniform{});
    load.D.col(k) = dual.d(load.f[k], extra ? 0.0 : setup.load_factor(unit));
    load.e.col(k) = dual.e(load.f[k]);
  }
  return load;
}

// ε̄ = W u (engineering shear) as coefficients: per component k, on λ (−B K⁺ wₖ), on α (R̂ᵀwₖ)
// and on the load columns (wₖᵀK⁺f). Per extra column k one more row, −fₖᵀu/|Ω|: for ε33 the part
// of σ33 that u gives, ⟨λ (εxx + εyy)⟩ (f₃₃ the load of ε33 = 1, which is −∫Bᵀλ(1, 1, 0) dA; the
// rest of σ33, ⟨λ + 2μ⟩ ε33, is added after the elimination); for ΔT its work conjugate in the
// same sense, −⟨β (εxx + εyy)⟩, whose only use is reciprocity: its dependence on σ̄ is minus
// ε̄'s on ΔT, and on p the openings' on ΔT.
struct StrainMap {
  Eigen::MatrixXd lambda, alpha, sigma;
};

StrainMap strain_map(const FetiSetup& setup, const DualProblem& dual, const MacroLoad& load, int n_macro) {
  const int m = dual.constraints().n_rows(), n_load = static_cast<int>(load.f.size());
  Eigen::MatrixXd W = boundary_strain_matrix(setup.mesh(), setup.n_dofs());
  W.row(2) *= 2;  // the boundary formula gives tensor shear; the law's is engineering (core/strain.hpp)
  StrainMap T{Eigen::MatrixXd(n_load, m), Eigen::MatrixXd(n_load, dual.G().rows()), Eigen::MatrixXd(n_load, n_load)};
  const Eigen::VectorXd no_lambda = Eigen::VectorXd::Zero(m);
  for (int k = 0; k < n_load; ++k) {
    const Eigen::VectorXd w = k >= n_macro ? (-load.f[k] / setup.volume()).eval() : W.row(k).transpose().eval();
    const Eigen::VectorXd v = dual.K_plus_residual(w, no_lambda);
    T.lambda.row(k) = -dual.d(w, 0.0).transpose();
    T.alpha.row(k) = dual.e(w).transpose();
    for (int j = 0; j < n_load; ++j) T.sigma(k, j) = v.dot(load.f[j]);
  }
  return T;
}

// The interface rows' bounds and kinds, in physical units (forces, not the weighted rows): the
// bonded ones as the rows have them, the broken ones by the bond rule.
void set_rows(law::CondensedCell& cell, const Constraints& con, const std::vector<int>& I) {
  namespace bond = law::bond;
  const int nI = static_cast<int>(I.size());
  cell.pair.resize(nI);
  cell.tangential.resize(nI);
  cell.lower_bonded.resize(nI);
  cell.upper_bonded.resize(nI);
  cell.lower_broken.resize(nI);
  cell.upper_broken.resize(nI);
  for (int i = 0; i < nI; ++i) {
    const int r = I[i];
    const double w = con.weight(r);
    cell.pair[i] = con.pair[r];
    cell.tangential[i] = con.kind[r] == RowKind::tangential;
    cell.lower_bonded(i) = con.lower(r) * w;
    cell.upper_bonded(i) = con.upper(r) * w;
    const bond::Bounds broken =
        bond::bounds(cell.tangential[i] ? bond::Kind::tangential : bond::Kind::normal, bond::State::broken, 0, 0, 0);
    cell.lower_broken(i) = broken.lower;
    cell.upper_broken(i) = broken.upper;
  }
}

}  // namespace

namespace {

// The rigid-body modes as rows of G and e and as columns of T.alpha, split into M, those the rows
// E other than the interface see (the matrix, the macro DOFs), and N, those only interface rows
// see (the fibres). A combination of modes the E rows see one by one may still escape them
// jointly (an RVE's fibre cut by the edges: its pieces spinning together about its centre, which
// the periodic rows between them do not see): such combinations Z, the null space of G_ME G_MEᵀ,
// join N, and M keeps its complement W.
struct Modes {
  Eigen::MatrixXd G_M, G_N, e_M, e_N, alpha_M, alpha_N;
};

// The boundary's motion is the macro strain's rows (n_macro); σ33's row, zero on rigid motions
// identically, would only add its round-off (check_fibres_still).
Modes split_modes(const Eigen::MatrixXd& G, const std::vector<int>& E, const MacroLoad& load, const StrainMap& T,
                  int n_macro) {
  const int m = static_cast<int>(G.cols()), n_load = static_cast<int>(load.e.cols());
  std::vector<int> M, N;
  for (Eigen::Index g = 0; g < G.rows(); ++g) {
    bool seen = false;
    for (int r : E) seen = seen || G(g, r) != 0;
    (seen ? M : N).push_back(static_cast<int>(g));
  }
  Modes out{pick(G, M, all(m)),
            pick(G, N, all(m)),
            pick(load.e, M, all(n_load)),
            pick(load.e, N, all(n_load)),
            pick(T.alpha, all(n_load), M),
            pick(T.alpha, all(n_load), N)};
  const Eigen::MatrixXd G_ME = pick(G, M, E);
  const NullSplit split = split_null_space(G_ME * G_ME.transpose());
  if (split.null.cols() == 0) return out;
  // A combination no row sees at all (that spin also escapes the interface's normal rows) is
  // no constraint: the dual problem leaves it undetermined (DualProblem::with_joint_null_modes)
  // and so does the law; it must carry no load and move no boundary.
  std::vector<int> constrained;
  for (Eigen::Index j = 0; j < split.null.cols(); ++j) {
    const Eigen::VectorXd z = split.null.col(j);
    if ((z.transpose() * out.G_M).norm() > null_mode_tolerance * out.G_M.norm()) {
      constrained.push_back(static_cast<int>(j));
      continue;
    }
    if ((z.transpose() * out.e_M).norm() > load_round_off * std::max(load.e.norm(), 1e-300) ||
        (out.alpha_M.topRows(n_macro) * z).norm() > null_mode_tolerance * T.alpha.topRows(n_macro).norm())
      throw InputError("a rigid motion no row sees is loaded or moves the cell's boundary: this cell has no law");
  }
  const Eigen::MatrixXd& W = split.range;
  const Eigen::MatrixXd Z = pick(split.null, all(M.size()), constrained);
  const auto stack = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    Eigen::MatrixXd c(a.rows() + b.rows(), a.cols());
    c << a, b;
    return c;
  };
  const auto beside = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    Eigen::MatrixXd c(a.rows(), a.cols() + b.cols());
    c << a, b;
    return c;
  };
  out.G_N = stack(out.G_N, Z.transpose() * out.G_M);
  out.e_N = stack(out.e_N, Z.transpose() * out.e_M);
  out.alpha_N = beside(out.alpha_N, out.alpha_M * Z);
  out.G_M = W.transpose() * out.G_M;
  out.e_M = W.transpose() * out.e_M;
  out.alpha_M = out.alpha_M * W;
  return out;
}

// The blocks of the eliminated system that involve the interface: its columns are the interface
// rows I themselves (the whole cell) or the combinations V_s of them (a basis, condense_on_solutions),
// in the scaled rows of B. F_EE is always the rows E's own block.
struct InterfaceBlocks {
  Eigen::MatrixXd F_EE, F_EI, F_II, D_I, G_MI, lambda_I;
};

// The cell on its interface columns, with λ_E and α_M eliminated (docs/method.md §16a), in the
// scaled rows: H = ∂(opening)/∂p, Y = ∂(opening)/∂σ̄, E_p = ∂ε̄/∂p, S₀ = ∂ε̄/∂σ̄.
struct Eliminated {
  Eigen::MatrixXd H, Y, E_p, S0;
};

Eliminated eliminate(const InterfaceBlocks& b, const Modes& modes, const MacroLoad& load, const StrainMap& T,
                     const std::vector<int>& E) {
  const int n_load = static_cast<int>(load.D.cols());
  const int mE = static_cast<int>(E.size()), nM = static_cast<int>(modes.G_M.rows());
  const Eigen::Index nI = b.F_EI.cols();
  const std::vector<int> rows_M = all(nM);
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(mE + nM, mE + nM);
  K.topLeftCorner(mE, mE) = b.F_EE;
  K.topRightCorner(mE, nM) = pick(modes.G_M, rows_M, E).transpose();
  K.bottomLeftCorner(nM, mE) = pick(modes.G_M, rows_M, E);
  Eigen::MatrixXd rhs_p(mE + nM, nI), rhs_s(mE + nM, n_load);
  rhs_p << -b.F_EI, -b.G_MI;
  rhs_s << pick(load.D, E, all(n_load)), modes.e_M;
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(K);
  const Eigen::MatrixXd X_p = lu.solve(rhs_p), X_s = lu.solve(rhs_s);
  const double solve_error = std::max((K * X_p - rhs_p).norm() / std::max(rhs_p.norm(), 1e-300),
                                      (K * X_s - rhs_s).norm() / std::max(rhs_s.norm(), 1e-300));
  if (!(solve_error < elimination_tolerance))
    throw InputError("the cell's rows other than the interface do not hold it (the eliminated system is singular)");
  const auto X_pE = X_p.topRows(mE), X_pM = X_p.bottomRows(nM), X_sE = X_s.topRows(mE), X_sM = X_s.bottomRows(nM);
  const Eigen::MatrixXd lambda_E = pick(T.lambda, all(n_load), E);
  Eliminated out;
  out.H = b.F_II + b.F_EI.transpose() * X_pE + b.G_MI.transpose() * X_pM;
  out.Y = b.D_I - b.F_EI.transpose() * X_sE - b.G_MI.transpose() * X_sM;
  out.E_p = b.lambda_I + lambda_E * X_pE - modes.alpha_M * X_pM;
  out.S0 = T.sigma + lambda_E * X_sE - modes.alpha_M * X_sM;
  return out;
}

// What both condensations share: the dual problem of the intact cell, its rows split into the
// interface I and the others E, the macro load, the strain map and the rigid modes split.
struct Prepared {
  std::unique_ptr<DualProblem> dual;
  std::vector<int> I, E;
  MacroLoad load;
  StrainMap T;
  Modes modes;
  int n_macro = 3;
  // The load columns: n_macro, and the strain along the fibres (a scene's [load] macro = "full")
  // and the temperature change (both phases expand) beyond them, condense only (not on a basis).
  Extras extras;
  int n_load = 3;
  BondState intact;
};

Prepared prepare(const FetiSetup& setup, int max_rows, const Extras& extras) {
  const Scene& scene = setup.scene();
  const mesh::Mesh& mesh = setup.mesh();
  if (scene.load.boundary == Boundary::edges)
    throw InputError("the edges boundary is a structure, not a cell: it has no cell law");
  if (scene.load.body_force[0] != 0 || scene.load.body_force[1] != 0)
    throw InputError("a cell with a body force has no homogeneous law: set [load] body_force = [0, 0]");
  Prepared p;
  p.n_macro = scene.load.boundary == Boundary::symmetry ? 2 : 3;
  p.extras = extras;
  p.intact = intact_bonds(mesh, scene.interface);
  p.dual = std::make_unique<DualProblem>(setup, build_constraints(mesh, scene, p.intact));
  const Constraints& con = p.dual->constraints();
  const int m = con.n_rows();
  if (m > max_rows)
    throw InputError("the cell has " + std::to_string(m) + " constraint rows, more than the " +
                     std::to_string(max_rows) + " a dense condensation pays for");
  for (int r = 0; r < m; ++r) (is_interface(con.kind[r]) ? p.I : p.E).push_back(r);
  p.load = macro_load(setup, *p.dual, p.n_macro, p.extras);
  p.n_load = static_cast<int>(p.load.f.size());
  p.T = strain_map(setup, *p.dual, p.load, p.n_macro);
  // The rigid-body modes' rows of G scaled to unit length, D = diag(1/‖G_g‖), with their loads e
  // (rows) and the strain map's α (columns), so that the law is unchanged (G p = 0 is the same
  // rows; a multiplier of a scaled row scales back through α). A rotation's row carries lengths
  // and a translation's none: unscaled, the split below measured the round-off of one against
  // the size of the other, and a cell of size 3e4 lost its law ("a macro stress loads a body held
  // only by interface rows").
  Eigen::MatrixXd G(p.dual->G());
  Eigen::VectorXd D(G.rows());
  for (Eigen::Index g = 0; g < G.rows(); ++g) D(g) = G.row(g).norm() > 0 ? 1 / G.row(g).norm() : 1.0;
  G = D.asDiagonal() * G;
  p.load.e = D.asDiagonal() * p.load.e;
  p.T.alpha = p.T.alpha * D.asDiagonal();
  p.modes = split_modes(G, p.E, p.load, p.T, p.n_macro);
  for (Eigen::Index g = 0; g < p.modes.e_N.rows(); ++g)
    if (p.modes.e_N.row(g).norm() > load_round_off * std::max(p.load.e.norm(), 1e-300))
      throw InputError("a macro stress loads a body held only by interface rows: this cell has no condensed law");
  return p;
}

// The macro strain's rows only: σ33's row (the strain along the fibres) is zero on every rigid
// motion identically, which strains nothing, and its round-off is not a motion of the boundary.
void check_fibres_still(const Prepared& p) {
  const Eigen::MatrixXd alpha_N = p.modes.alpha_N.topRows(p.n_macro);
  if (alpha_N.cols() > 0 && alpha_N.norm() > null_mode_tolerance * p.T.alpha.topRows(p.n_macro).norm())
    throw InputError("a body held only by interface rows moves the cell's boundary: this cell has no condensed law");
}

// Reciprocity: the strain's dependence on p is the opening's on σ̄, |Ω| E_p = −Yᵀ; with the
// symmetry of H and S₀ this is the symmetry of 𝓗 (relative).
double reciprocity(const Eigen::MatrixXd& H, const Eigen::MatrixXd& Y, const Eigen::MatrixXd& E_p,
                   const Eigen::MatrixXd& S0, double volume) {
  return std::max({(volume * E_p + Y.transpose()).norm() / std::max(Y.norm(), 1e-300),
                   (H - H.transpose()).norm() / std::max(H.norm(), 1e-300),
                   (S0 - S0.transpose()).norm() / std::max(S0.norm(), 1e-300)});
}

// The strain along the fibres (docs/method.md §16a): from the eliminated system's extra column
// and row (load column and strain row n_macro, physical units), A33, C33 and y33 into `cell`,
// each symmetrised by its reciprocity, which is measured (relative) and returned: the open cell's
// ε̄ per unit ε33 against minus its σ33 per unit σ̄, and y33 (the openings per unit ε33) against
// |Ω| ∂σ33/∂p.
double set_longitudinal(const FetiSetup& setup, const Eigen::MatrixXd& Y, const Eigen::MatrixXd& E_p,
                        const Eigen::MatrixXd& S0, int m, law::CondensedCell& cell) {
  const double volume = setup.volume();
  double zz = 0;  // ⟨λ + 2μ⟩: σ33 of ε33 = 1 with u = 0
  average_stress(setup.mesh(), setup.scene().fibre, setup.scene().matrix, Eigen::VectorXd::Zero(setup.mesh().dim_u()),
                 {1.0}, &zz);
  const Eigen::VectorXd a = S0.col(m).head(m), b = S0.row(m).head(m).transpose();
  const Eigen::VectorXd y = Y.col(m), g = volume * E_p.row(m).transpose();
  cell.longitudinal = 1;
  cell.A33 = 0.5 * (a - b);
  cell.C33 = Eigen::MatrixXd::Constant(1, 1, S0(m, m) + zz);
  cell.y33 = 0.5 * (y + g);
  // Relative to the in-plane columns too: where the phases' ν agree, A33 and y33 are round-off.
  return std::max((a + b).norm() / std::max({a.norm(), S0.topLeftCorner(m, m).norm(), 1e-300}),
                  (y - g).norm() / std::max({y.norm(), Y.leftCols(m).norm(), 1e-300}));
}

// The temperature change (docs/theory/model.md §1a): from the eliminated system's ΔT column and
// row (index t, after ε33's where the cell has it), AT, yT and, with ε33, CT into `cell`, each
// symmetrised by its reciprocity, which is measured (relative) and returned, as ε33's: the open
// cell's ε̄ per kelvin against minus its ΔT row per unit σ̄, the openings per kelvin against
// |Ω| times the row's dependence on p, and σ33 per kelvin (u's part both ways, plus the phases'
// own −⟨β33⟩ at u = 0).
double set_thermal(const FetiSetup& setup, const Eigen::MatrixXd& Y, const Eigen::MatrixXd& E_p,
                   const Eigen::MatrixXd& S0, int m, bool longitudinal, law::CondensedCell& cell) {
  const double volume = setup.volume();
  const int t = m + (longitudinal ? 1 : 0);
  const Eigen::VectorXd a = S0.col(t).head(m), b = S0.row(t).head(m).transpose();
  const Eigen::VectorXd y = Y.col(t), g = volume * E_p.row(t).transpose();
  cell.thermal = 1;
  cell.AT = 0.5 * (a - b);
  cell.yT = 0.5 * (y + g);
  // Each relative to its own pair (kelvin's units: the in-plane columns' are another scale).
  double error = std::max((a + b).norm() / std::max({a.norm(), b.norm(), 1e-300}),
                          (y - g).norm() / std::max({y.norm(), g.norm(), 1e-300}));
  if (longitudinal) {
    double zz = 0;  // −⟨β33⟩: σ33 of ΔT = 1 with u = 0
    average_stress(setup.mesh(), setup.scene().fibre, setup.scene().matrix, Eigen::VectorXd::Zero(setup.mesh().dim_u()),
                   {0.0, 1.0}, &zz);
    cell.CT = Eigen::MatrixXd::Constant(1, 1, 0.5 * (S0(m, t) + S0(t, m)) + zz);
    error = std::max(error, std::abs(S0(m, t) - S0(t, m)) /
                                std::max({std::abs(zz), std::abs(S0(m, t)), std::abs(S0(t, m)), 1e-300}));
  } else {
    cell.CT.resize(0, 1);
  }
  return error;
}

// The shear along the fibres (docs/method.md §16a): the antiplane problem condensed onto the
// pairs (primal::condense_longitudinal_shear), with a row per pair where bonds carry shear (the
// tangential strength s_t > 0); a pair's strength along z is its in-plane tangential row's, s_t L
// (shear_strengths).
void set_shear(const FetiSetup& setup, law::CondensedCell& cell) {
  const Scene& scene = setup.scene();
  const double st = scene.interface.tangential_strength;
  const primal::CondensedShear z = primal::condense_longitudinal_shear(setup.mesh(), scene.fibre, scene.matrix, st > 0);
  cell.shear = 2;
  cell.D0z = z.D0;
  if (!(st > 0)) return;
  cell.shear_rows = cell.n_pairs;
  cell.pair_z.resize(static_cast<std::size_t>(cell.n_pairs));
  std::iota(cell.pair_z.begin(), cell.pair_z.end(), 0);
  cell.Yz = z.Y;
  cell.Hz = z.H;
  cell.Gz = z.G;
  const std::vector<double> strength = shear_strengths(setup.mesh(), scene);
  cell.strength_z = Eigen::Map<const Eigen::VectorXd>(strength.data(), static_cast<Eigen::Index>(strength.size()));
}

}  // namespace

law::CondensedCell condense(const FetiSetup& setup, int max_rows) {
  const auto start = std::chrono::steady_clock::now();
  const Scene& scene = setup.scene();
  const Prepared p = prepare(
      setup, max_rows,
      {.longitudinal = scene.load.macro == Macro::full, .thermal = scene.fibre.expands && scene.matrix.expands});
  const Constraints& con = p.dual->constraints();
  const std::vector<int>& I = p.I;
  const int n_macro = p.n_macro, n_load = p.n_load;
  const Eigen::MatrixXd F = p.dual->explicit_F();
  InterfaceBlocks blocks{pick(F, p.E, p.E),
                         pick(F, p.E, I),
                         pick(F, I, I),
                         pick(p.load.D, I, all(n_load)),
                         pick(p.modes.G_M, all(p.modes.G_M.rows()), I),
                         pick(p.T.lambda, all(n_load), I)};
  Eliminated x = eliminate(blocks, p.modes, p.load, p.T, p.E);
  check_fibres_still(p);

  // Physical interface forces p = w λ_scaled: H, Y, E_p and G scaled by 1/w.
  const int nI = static_cast<int>(I.size());
  Eigen::VectorXd inverse_weight(nI);
  for (int i = 0; i < nI; ++i) inverse_weight(i) = 1 / con.weight(I[i]);
  const Eigen::MatrixXd H = inverse_weight.asDiagonal() * x.H * inverse_weight.asDiagonal();
  const Eigen::MatrixXd Y_all = inverse_weight.asDiagonal() * x.Y;
  const Eigen::MatrixXd E_p_all = x.E_p * inverse_weight.asDiagonal();
  const Eigen::MatrixXd Y = Y_all.leftCols(n_macro), E_p = E_p_all.topRows(n_macro);
  const Eigen::MatrixXd S0 = x.S0.topLeftCorner(n_macro, n_macro);
  const double volume = setup.volume();
  law::CondensedCell cell;
  cell.operator_applications = 2 * n_load;  // d and the strain map; F comes from the subdomains' blocks
  cell.reciprocity_error = reciprocity(H, Y, E_p, S0, volume);
  if (p.extras.longitudinal)
    cell.reciprocity_error =
        std::max(cell.reciprocity_error, set_longitudinal(setup, Y_all, E_p_all, x.S0, n_macro, cell));
  if (p.extras.thermal)
    cell.reciprocity_error = std::max(cell.reciprocity_error,
                                      set_thermal(setup, Y_all, E_p_all, x.S0, n_macro, p.extras.longitudinal, cell));
  cell.n_macro = n_macro;
  cell.volume = volume;
  cell.S0 = 0.5 * (S0 + S0.transpose());
  cell.H = 0.5 * (H + H.transpose());
  cell.Y = 0.5 * (Y - volume * E_p.transpose());
  cell.G = pick(p.modes.G_N, all(p.modes.G_N.rows()), I) * inverse_weight.asDiagonal();
  cell.n_pairs = static_cast<int>(setup.mesh().interface_pairs.size());
  cell.bonded = p.intact;
  set_rows(cell, con, I);
  if (p.extras.longitudinal && scene.load.boundary == Boundary::periodic) set_shear(setup, cell);
  cell.seconds = seconds_since(start);
  return cell;
}

law::CondensedCell condense_on_solutions(const FetiSetup& setup, const std::vector<Eigen::VectorXd>& lambdas) {
  const auto start = std::chrono::steady_clock::now();
  const Prepared p = prepare(setup, std::numeric_limits<int>::max(), {});
  const Constraints& con = p.dual->constraints();
  const DualProblem& dual = *p.dual;
  if (setup.scene().interface.has_adhesion())
    throw InputError(
        "the cell has adhesion: its bonded rows carry tension, which nonnegative combinations of "
        "its solutions cannot represent");
  const int n_macro = p.n_macro, m = con.n_rows(), mE = static_cast<int>(p.E.size());
  // V_s: each solution's interface forces scaled to unit largest entry (p_j/‖p_j‖∞), in the
  // scaled rows of B (λ = p/w) and zero on E; a solution without interface force (every contact
  // open) is no column.
  Eigen::MatrixXd Vs = Eigen::MatrixXd::Zero(m, static_cast<Eigen::Index>(lambdas.size()));
  int k = 0;
  for (const Eigen::VectorXd& lambda : lambdas) {
    if (lambda.size() != m)
      throw InputError("a solution has " + std::to_string(lambda.size()) + " multipliers, the intact cell " +
                       std::to_string(m) + " rows");
    double largest = 0;
    for (const int r : p.I) largest = std::max(largest, std::abs(lambda(r)));
    if (!std::isfinite(largest)) throw InputError("a solution's interface forces are not finite");
    if (!(largest > 0)) continue;
    for (const int r : p.I) Vs(r, k) = lambda(r) / largest / con.weight(r);
    ++k;
  }
  if (k == 0) throw InputError("no solution has an interface force: the basis has no column");
  Vs.conservativeResize(Eigen::NoChange, k);
  // F on the rows E one by one and on the basis: mE + k applications, no dense F of all rows.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(m), y(m);
  Eigen::MatrixXd F_E(m, mE), F_V(m, k);
  for (int c = 0; c < mE; ++c) {
    x(p.E[c]) = 1;
    dual.apply_F(x, y);
    F_E.col(c) = y;
    x(p.E[c]) = 0;
  }
  for (int j = 0; j < k; ++j) {
    x = Vs.col(j);
    dual.apply_F(x, y);
    F_V.col(j) = y;
  }
  const Eigen::MatrixXd V_I = pick(Vs, p.I, all(k));
  InterfaceBlocks blocks{pick(F_E, p.E, all(mE)),
                         pick(F_V, p.E, all(k)),
                         Vs.transpose() * F_V,
                         V_I.transpose() * pick(p.load.D, p.I, all(n_macro)),
                         pick(p.modes.G_M, all(p.modes.G_M.rows()), p.I) * V_I,
                         pick(p.T.lambda, all(n_macro), p.I) * V_I};
  const Eliminated e = eliminate(blocks, p.modes, p.load, p.T, p.E);
  check_fibres_still(p);
  const double volume = setup.volume();
  law::CondensedCell macro;
  macro.n_macro = n_macro;
  macro.volume = volume;
  macro.S0 = 0.5 * (e.S0 + e.S0.transpose());
  law::CondensedCell cell =
      law::cell_of_rows(macro, 0.5 * (e.Y - volume * e.E_p.transpose()), law::with_basis_compliance(e.H));
  cell.reciprocity_error = reciprocity(e.H, e.Y, e.E_p, e.S0, volume);
  cell.operator_applications = 2 * n_macro + mE + k;
  cell.seconds = seconds_since(start);
  return cell;
}

}  // namespace dualcell::feti
