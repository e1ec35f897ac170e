#include "feti/condense.hpp"

#include <Eigen/Dense>
#include <chrono>
#include <limits>

#include "core/error.hpp"
#include "feti/constraints.hpp"
#include "feti/dual.hpp"
#include "feti/macro.hpp"

namespace dualcell::feti {

namespace {

bool is_interface(RowKind kind) { return kind == RowKind::normal || kind == RowKind::tangential; }

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
  W.row(2) *= 2;
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

// The interface rows' bounds and kinds, in physical units (forces, not the weighted rows).
void set_rows(law::CondensedCell& cell, const Constraints& con, const std::vector<int>& I) {
  constexpr double inf = std::numeric_limits<double>::infinity();
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
    cell.lower_broken(i) = 0;
    cell.upper_broken(i) = cell.tangential[i] ? 0 : inf;
  }
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
  const Eigen::MatrixXd G = Eigen::MatrixXd(dual.G());
  // The modes the other rows see (M: the matrix, the macro DOFs), and those only interface rows
  // see (N: the fibres).
  std::vector<int> M, N;
  for (Eigen::Index g = 0; g < G.rows(); ++g) {
    bool seen = false;
    for (int r : E) seen = seen || G(g, r) != 0;
    (seen ? M : N).push_back(static_cast<int>(g));
  }
  const MacroLoad load = macro_load(setup, dual, n_macro);
  const Eigen::MatrixXd& D = load.D;
  const Eigen::MatrixXd& e = load.e;
  for (int g : N)
    if (e.row(g).norm() > 1e-12 * std::max(e.norm(), 1e-300))
      throw InputError("a macro stress loads a body held only by interface rows: this cell has no condensed law");
  const StrainMap T = strain_map(setup, dual, load, n_macro);
  cell.operator_applications = 2 * n_macro;  // d and the strain map; F comes from the subdomains' blocks

  // Eliminate λ_E and α_M.
  const int mE = static_cast<int>(E.size()), nM = static_cast<int>(M.size()), nI = static_cast<int>(I.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(mE + nM, mE + nM);
  K.topLeftCorner(mE, mE) = pick(F, E, E);
  K.topRightCorner(mE, nM) = pick(G, M, E).transpose();
  K.bottomLeftCorner(nM, mE) = pick(G, M, E);
  Eigen::MatrixXd rhs_p(mE + nM, nI), rhs_s(mE + nM, n_macro);
  rhs_p << -pick(F, E, I), -pick(G, M, I);
  rhs_s << pick(D, E, all(n_macro)), pick(e, M, all(n_macro));
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(K);
  const Eigen::MatrixXd X_p = lu.solve(rhs_p), X_s = lu.solve(rhs_s);
  const double solve_error = std::max((K * X_p - rhs_p).norm() / std::max(rhs_p.norm(), 1e-300),
                                      (K * X_s - rhs_s).norm() / std::max(rhs_s.norm(), 1e-300));
  if (!(solve_error < 1e-8))
    throw InputError("the cell's rows other than the interface do not hold it (the eliminated system is singular)");
  const auto X_pE = X_p.topRows(mE), X_pM = X_p.bottomRows(nM), X_sE = X_s.topRows(mE), X_sM = X_s.bottomRows(nM);
  const Eigen::MatrixXd F_IE = pick(F, I, E), G_MI = pick(G, M, I);
  Eigen::MatrixXd H = pick(F, I, I) + F_IE * X_pE + G_MI.transpose() * X_pM;
  Eigen::MatrixXd Y = pick(D, I, all(n_macro)) - F_IE * X_sE - G_MI.transpose() * X_sM;
  Eigen::MatrixXd E_p =
      pick(T.lambda, all(n_macro), I) + pick(T.lambda, all(n_macro), E) * X_pE - pick(T.alpha, all(n_macro), M) * X_pM;
  Eigen::MatrixXd S0 = T.sigma + pick(T.lambda, all(n_macro), E) * X_sE - pick(T.alpha, all(n_macro), M) * X_sM;
  if (!N.empty() && pick(T.alpha, all(n_macro), N).norm() > 1e-10 * T.alpha.norm())
    throw InputError("a body held only by interface rows moves the cell's boundary: this cell has no condensed law");

  // Physical interface forces p = w λ_scaled: H, Y, E_p and G scaled by 1/w.
  Eigen::VectorXd inverse_weight(nI);
  for (int i = 0; i < nI; ++i) inverse_weight(i) = 1 / con.weight(I[i]);
  H = inverse_weight.asDiagonal() * H * inverse_weight.asDiagonal();
  Y = inverse_weight.asDiagonal() * Y;
  E_p = E_p * inverse_weight.asDiagonal();
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
  cell.G = pick(G, N, I) * inverse_weight.asDiagonal();
  cell.n_pairs = static_cast<int>(mesh.interface_pairs.size());
  cell.bonded = intact;
  set_rows(cell, con, I);
  cell.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cell;
}

}  // namespace dualcell::feti
