#include "feti/condense.hpp"

#include <Eigen/Dense>
#include <chrono>
#include <limits>

#include "core/error.hpp"
#include "feti/constraints.hpp"
#include "feti/dual.hpp"
#include "feti/macro.hpp"
#include "law/bond.hpp"

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

// The macro load per unit stress component k: the load f_k, the dual right-hand sides d_k and
// e_k of §6.
struct MacroLoad {
  std::vector<Eigen::VectorXd> f;
  Eigen::MatrixXd D, e;  // columns k
};

MacroLoad macro_load(const FetiSetup& setup, const DualProblem& dual, int n_macro) {
  MacroLoad load;
  load.f.resize(n_macro);
  load.D.resize(dual.constraints().n_rows(), n_macro);
  load.e.resize(dual.G().rows(), n_macro);
  for (int k = 0; k < n_macro; ++k) {
    const Eigen::Vector3d unit = Eigen::Vector3d::Unit(k);
    load.f[k] = setup.load(unit);
    load.D.col(k) = dual.d(load.f[k], setup.load_factor(unit));
    load.e.col(k) = dual.e(load.f[k]);
  }
  return load;
}

// ε̄ = W u (engineering shear) as coefficients: per component k, on λ (−B K⁺ wₖ), on α (R̂ᵀwₖ)
// and on σ̄ (wₖᵀK⁺f).
struct StrainMap {
  Eigen::MatrixXd lambda, alpha, sigma;
};

StrainMap strain_map(const FetiSetup& setup, const DualProblem& dual, const MacroLoad& load, int n_macro) {
  const int m = dual.constraints().n_rows();
  Eigen::MatrixXd W = boundary_strain_matrix(setup.mesh(), setup.n_dofs());
  W.row(2) *= 2;  // the boundary formula gives tensor shear; the law's is engineering (core/strain.hpp)
  StrainMap T{Eigen::MatrixXd(n_macro, m), Eigen::MatrixXd(n_macro, dual.G().rows()),
              Eigen::MatrixXd(n_macro, n_macro)};
  const Eigen::VectorXd no_lambda = Eigen::VectorXd::Zero(m);
  for (int k = 0; k < n_macro; ++k) {
    const Eigen::VectorXd w = W.row(k).transpose();
    const Eigen::VectorXd v = dual.K_plus_residual(w, no_lambda);
    T.lambda.row(k) = -dual.d(w, 0.0).transpose();
    T.alpha.row(k) = dual.e(w).transpose();
    for (int j = 0; j < n_macro; ++j) T.sigma(k, j) = v.dot(load.f[j]);
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

Modes split_modes(const Eigen::MatrixXd& G, const std::vector<int>& E, const MacroLoad& load, const StrainMap& T,
                  int n_macro) {
  const int m = static_cast<int>(G.cols());
  std::vector<int> M, N;
  for (Eigen::Index g = 0; g < G.rows(); ++g) {
    bool seen = false;
    for (int r : E) seen = seen || G(g, r) != 0;
    (seen ? M : N).push_back(static_cast<int>(g));
  }
  Modes out{pick(G, M, all(m)),
            pick(G, N, all(m)),
            pick(load.e, M, all(n_macro)),
            pick(load.e, N, all(n_macro)),
            pick(T.alpha, all(n_macro), M),
            pick(T.alpha, all(n_macro), N)};
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
        (out.alpha_M * z).norm() > null_mode_tolerance * T.alpha.norm())
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

// The cell on its interface rows I, with λ_E and α_M eliminated (docs/method.md §16a), in the
// scaled rows: H = ∂(opening)/∂p, Y = ∂(opening)/∂σ̄, E_p = ∂ε̄/∂p, S₀ = ∂ε̄/∂σ̄.
struct Eliminated {
  Eigen::MatrixXd H, Y, E_p, S0;
};

Eliminated eliminate(const Eigen::MatrixXd& F, const Modes& modes, const MacroLoad& load, const StrainMap& T,
                     const std::vector<int>& I, const std::vector<int>& E, int n_macro) {
  const Eigen::MatrixXd& D = load.D;
  const int mE = static_cast<int>(E.size()), nM = static_cast<int>(modes.G_M.rows());
  const int nI = static_cast<int>(I.size());
  const std::vector<int> rows_M = all(nM);
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(mE + nM, mE + nM);
  K.topLeftCorner(mE, mE) = pick(F, E, E);
  K.topRightCorner(mE, nM) = pick(modes.G_M, rows_M, E).transpose();
  K.bottomLeftCorner(nM, mE) = pick(modes.G_M, rows_M, E);
  Eigen::MatrixXd rhs_p(mE + nM, nI), rhs_s(mE + nM, n_macro);
  rhs_p << -pick(F, E, I), -pick(modes.G_M, rows_M, I);
  rhs_s << pick(D, E, all(n_macro)), modes.e_M;
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(K);
  const Eigen::MatrixXd X_p = lu.solve(rhs_p), X_s = lu.solve(rhs_s);
  const double solve_error = std::max((K * X_p - rhs_p).norm() / std::max(rhs_p.norm(), 1e-300),
                                      (K * X_s - rhs_s).norm() / std::max(rhs_s.norm(), 1e-300));
  if (!(solve_error < elimination_tolerance))
    throw InputError("the cell's rows other than the interface do not hold it (the eliminated system is singular)");
  const auto X_pE = X_p.topRows(mE), X_pM = X_p.bottomRows(nM), X_sE = X_s.topRows(mE), X_sM = X_s.bottomRows(nM);
  const Eigen::MatrixXd F_IE = pick(F, I, E), G_MI = pick(modes.G_M, rows_M, I);
  Eliminated out;
  out.H = pick(F, I, I) + F_IE * X_pE + G_MI.transpose() * X_pM;
  out.Y = pick(D, I, all(n_macro)) - F_IE * X_sE - G_MI.transpose() * X_sM;
  out.E_p = pick(T.lambda, all(n_macro), I) + pick(T.lambda, all(n_macro), E) * X_pE - modes.alpha_M * X_pM;
  out.S0 = T.sigma + pick(T.lambda, all(n_macro), E) * X_sE - modes.alpha_M * X_sM;
  return out;
}

}  // namespace

law::CondensedCell condense(const FetiSetup& setup, int max_rows) {
  const auto start = std::chrono::steady_clock::now();
  const Scene& scene = setup.scene();
  const mesh::Mesh& mesh = setup.mesh();
  if (scene.load.boundary == Boundary::edges)
    throw InputError("the edges boundary is a structure, not a cell: it has no cell law");
  if (scene.load.body_force[0] != 0 || scene.load.body_force[1] != 0)
    throw InputError("a cell with a body force has no homogeneous law: set [load] body_force = [0, 0]");
  const int n_macro = scene.load.boundary == Boundary::symmetry ? 2 : 3;

  const BondState intact = intact_bonds(mesh, scene.interface);
  const DualProblem dual(setup, build_constraints(mesh, scene, intact));
  const Constraints& con = dual.constraints();
  const int m = con.n_rows();
  if (m > max_rows)
    throw InputError("the cell has " + std::to_string(m) + " constraint rows, more than the " +
                     std::to_string(max_rows) + " a dense condensation pays for");
  std::vector<int> I, E;
  for (int r = 0; r < m; ++r) (is_interface(con.kind[r]) ? I : E).push_back(r);

  law::CondensedCell cell;
  const Eigen::MatrixXd F = dual.explicit_F();
  MacroLoad load = macro_load(setup, dual, n_macro);
  StrainMap T = strain_map(setup, dual, load, n_macro);
  // The rigid-body modes' rows of G scaled to unit length, D = diag(1/‖G_g‖), with their loads e
  // (rows) and the strain map's α (columns), so that the law is unchanged (G p = 0 is the same
  // rows; a multiplier of a scaled row scales back through α). A rotation's row carries lengths
  // and a translation's none: unscaled, the split below measured the round-off of one against
  // the size of the other, and a cell of size 3e4 lost its law ("a macro stress loads a body held
  // only by interface rows").
  Eigen::MatrixXd G(dual.G());
  Eigen::VectorXd D(G.rows());
  for (Eigen::Index g = 0; g < G.rows(); ++g) D(g) = G.row(g).norm() > 0 ? 1 / G.row(g).norm() : 1.0;
  G = D.asDiagonal() * G;
  load.e = D.asDiagonal() * load.e;
  T.alpha = T.alpha * D.asDiagonal();
  const Modes modes = split_modes(G, E, load, T, n_macro);
  for (Eigen::Index g = 0; g < modes.e_N.rows(); ++g)
    if (modes.e_N.row(g).norm() > load_round_off * std::max(load.e.norm(), 1e-300))
      throw InputError("a macro stress loads a body held only by interface rows: this cell has no condensed law");
  cell.operator_applications = 2 * n_macro;  // d and the strain map; F comes from the subdomains' blocks
  Eliminated x = eliminate(F, modes, load, T, I, E, n_macro);
  if (modes.alpha_N.cols() > 0 && modes.alpha_N.norm() > null_mode_tolerance * T.alpha.norm())
    throw InputError("a body held only by interface rows moves the cell's boundary: this cell has no condensed law");

  // Physical interface forces p = w λ_scaled: H, Y, E_p and G scaled by 1/w.
  const int nI = static_cast<int>(I.size());
  Eigen::VectorXd inverse_weight(nI);
  for (int i = 0; i < nI; ++i) inverse_weight(i) = 1 / con.weight(I[i]);
  const Eigen::MatrixXd H = inverse_weight.asDiagonal() * x.H * inverse_weight.asDiagonal();
  const Eigen::MatrixXd Y = inverse_weight.asDiagonal() * x.Y;
  const Eigen::MatrixXd E_p = x.E_p * inverse_weight.asDiagonal();
  const Eigen::MatrixXd& S0 = x.S0;
  const double volume = setup.volume();
  // Reciprocity: the strain's dependence on p is the opening's on σ̄, |Ω| E_p = −Yᵀ; with the
  // symmetry of H and S₀ this is the symmetry of 𝓗.
  const double scale_Y = std::max(Y.norm(), 1e-300);
  cell.reciprocity_error = std::max({(volume * E_p + Y.transpose()).norm() / scale_Y,
                                     (H - H.transpose()).norm() / std::max(H.norm(), 1e-300),
                                     (S0 - S0.transpose()).norm() / std::max(S0.norm(), 1e-300)});
  cell.n_macro = n_macro;
  cell.volume = volume;
  cell.S0 = 0.5 * (S0 + S0.transpose());
  cell.H = 0.5 * (H + H.transpose());
  cell.Y = 0.5 * (Y - volume * E_p.transpose());
  cell.G = pick(modes.G_N, all(modes.G_N.rows()), I) * inverse_weight.asDiagonal();
  cell.n_pairs = static_cast<int>(mesh.interface_pairs.size());
  cell.bonded = intact;
  set_rows(cell, con, I);
  cell.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cell;
}

}  // namespace dualcell::feti
