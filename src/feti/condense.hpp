#pragma once
// The exact law of a cell (law/condensed.hpp): the cell condensed onto its interface rows
// (docs/method.md §16a), from the FETI data of its mesh and materials.
//
// The dual operator F = B K⁺ Bᵀ is formed explicitly from the subdomains' blocks F_s (the same
// blocks as the explicit dual operator, DualProblem::explicit_F), with G and the macro load's d
// and e. The rows E that are not interface
// rows (glue, periodic, Dirichlet) and the rigid modes M they see are eliminated from the
// stationarity conditions of the dual problem,
//
//   [F_EE  G_MEᵀ] [ λ_E]   [d_E − F_EI p]
//   [G_ME   0   ] [−α_M] = [e_M − G_MI p],
//
// by a dense LU; what is left on the interface forces p is H p − Y σ̄ (the reduced gradient),
// and the macro strain ε̄ = W u with u = K⁺(f − Bᵀλ) + R̂α is linear in p and σ̄ (S₀σ̄ + E_p p).
// The modes N that only interface rows see (the fibres) stay as the equality rows G_N p = e_N.
// Reciprocity, |Ω| E_p = −Yᵀ, is measured (CondensedCell::reciprocity_error), not assumed.
#include "feti/setup.hpp"
#include "law/condensed.hpp"

namespace dualcell::feti {

// Beyond this many rows of B the dense condensation no longer pays: F (summed from the
// subdomains' blocks F_s) and the eliminated system are dense, 8·rows² bytes each (72 MB at 3000
// rows), and the law's QP evaluates a dense matrix of the interface rows at every material point;
// the compact law stands alone there. The law's readers refuse more interface rows than this.
inline constexpr int max_condensed_rows = law::max_cell_rows;

// Every rank of setup.group() must call it (it applies F). An InputError, saying why, for a
// scene that has no cell law (the edges boundary; a body force: the law would not be
// homogeneous) or whose B has more than max_rows rows.
law::CondensedCell condense(const FetiSetup& setup, int max_rows = max_condensed_rows);

// The cell on a basis of its own solutions (docs/method.md §16c): p = Vμ, μ ≥ 0, with v_j the
// interface part of lambdas[j] (a contact solution of the intact cell, Solution::lambda, per row
// of B) scaled to unit largest entry; a solution without interface force (every contact open) is
// no column. The same cell as law::cell_on_basis(condense(setup), V),
// without a dense matrix of the cell's rows: F is applied to the rows other than the interface
// one by one and to V's columns (rows E + k applications), so it has no row cap. Every rank of
// setup.group() must call it. An InputError for a scene condense refuses, a cell with adhesion
// (its bonded rows carry tension: no cone of solutions), a λ of another size, or no column.
law::CondensedCell condense_on_solutions(const FetiSetup& setup, const std::vector<Eigen::VectorXd>& lambdas);

}  // namespace dualcell::feti
