#pragma once
// A small dense convex QP solved exactly by a primal active-set method (docs/method.md §16a):
//
//   min ½ xᵀA x − bᵀx   s.t.  C x = 0,  l ≤ x ≤ u,
//
// A symmetric, positive semidefinite and positive definite on ker C; l ≤ 0 ≤ u, so x = 0 is
// feasible. It is the exact law of a cell (law/condensed.hpp): tens to a few hundred unknowns,
// a few equality rows. Unlike MPRGP it stops at the exact solution of a finite system (to
// round-off, not to a tolerance) and returns the exact active set, which the consistent tangent
// needs.
//
// Each iteration solves the equality-constrained problem with the variables of the working set
// held at their bounds (the KKT system of the free ones, equilibrated and factorised by LU
// with partial pivoting), then either steps to the first bound met (which joins the working
// set) or, at the solution of that subproblem, releases the bound whose multiplier has the
// wrong sign by the most (docs/method.md §16a). Every step keeps x
// feasible and does not increase the objective; a working set never repeats once the objective
// has decreased, so the method terminates.
//
// Warm start: `active` in is the previous answer's active set. It is tried first as it stands
// (the common case along a path: the same set, one solve); while its subproblem's solution is not
// feasible, up to a few corrections of it are tried in the manner of block principal pivoting (a
// variable put beyond a bound is held there, a held one whose multiplier has the wrong sign is
// freed), and only when none is feasible does the method start from x = 0 with every bound at
// zero held. Either way held
// variables are freed until the free columns of C have its full rank (a working set must be
// linearly independent for its multipliers to say which bound to release). The factorisation
// of the last working set is kept and reused while the free set stays the same, and up to 16
// earlier ones (as many as fit in 1 MB) are kept beside it: a free set met again takes its own.
// A free set that differs from the kept one's by a few variables (an active-set step, a round of
// a debond cascade) is not factorised again: its KKT system is the kept one bordered by a
// column per variable freed or held, solved through the kept LU and the small Schur complement
// of the border (docs/method.md §16a, "Bordered updates"). One LU of k unknowns costs ⅔k³, a
// border column 2k², so a step of a 256-row cell costs a hundredth of a factorisation.
//
// One object is one problem: A and C are bound at construction (referenced, not copied: the
// caller keeps them alive and unchanged); b and the bounds change from call to call. Another A
// or C is another object, so a kept factorisation can never belong to other matrices.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cstdint>
#include <string>
#include <vector>

namespace dualcell::qp {

enum class Bound : std::int8_t { free = 0, lower = -1, upper = 1 };

struct DenseQpResult {
  Eigen::VectorXd x;
  // Multipliers: A x − b + Cᵀμ = ν with ν_i ≥ 0 at a lower bound, ≤ 0 at an upper one, 0 where
  // free (computed for the held variables only; 0 where free by the subproblem).
  Eigen::VectorXd mu, nu;
  int iterations = 0;      // subproblems solved
  int factorisations = 0;  // of those, the ones that needed a new factorisation
  int updates = 0;         // and the ones served by bordering the kept factorisation
  bool converged = false;
  std::string message;  // why not, when not converged
};

class DenseActiveSet {
 public:
  // How a new free set gets its KKT system solved: the kept factorisation bordered where it
  // differs by a few variables (the default), or always a factorisation of its own (the
  // reference the bordered solves are tested against).
  enum class Updates { bordered, factorise_each };
  // The problem's A (n × n) and C (n_c × n; 0 × n or empty for none), for the object's life.
  DenseActiveSet(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C, Updates updates = Updates::bordered);
  DenseActiveSet(const DenseActiveSet&) = delete;
  DenseActiveSet& operator=(const DenseActiveSet&) = delete;

  // Solves the QP for b and the bounds l, u; `active` (size n, or empty for none) is the warm
  // start in and the active set of the solution out.
  DenseQpResult solve(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                      std::vector<Bound>& active);
  // dx/db at the last solution's active set (the free variables move, the bound ones do not),
  // one column per column of db: what the tangent of a law needs.
  Eigen::MatrixXd sensitivity(const Eigen::MatrixXd& db) const;
  // Counts the factorisations: sensitivity() gives the same answer while it stays the same
  // (the caller may keep what it derived from it, e.g. a tangent).
  long generation() const { return generation_; }

 private:
  // The KKT system of the free set free_: [A_FF C_Kᵀ; C_K 0], C_K the independent rows of C_F,
  // factorised; it becomes the base (no border).
  void factorise();
  // The independent rows of C over the free set `free` and which free variables they pin.
  void rows_of_free_set(const std::vector<int>& free, std::vector<int>& rows, std::vector<char>& pinned) const;
  // The free set `free` as the base bordered (see the file comment); false where the base is
  // small or ill-conditioned, the set differs from it by more than max_border variables, the
  // base's rows of C do not alone have C's rank over it, or its Schur complement is singular to
  // round-off (a factorisation of its own then decides).
  bool border(const std::vector<int>& free);
  // The border's columns for variables `vars` (added: freed, else held), those of the current
  // border reused: the equilibrated B̂ (a freed variable's column of A over the base's free
  // variables and of C over its rows; a held one's unit column), Ẑ = K̂⁻¹B̂, and their scales.
  void border_columns(const std::vector<int>& vars, const std::vector<char>& added, Eigen::MatrixXd& B,
                      Eigen::MatrixXd& Z, Eigen::VectorXd& scale) const;
  // The current free set's KKT system solved in place for the columns of v, in the bordered
  // unknowns (the base's free variables and rows, then one per border variable), unscaled.
  void kkt_solve(Eigen::Ref<Eigen::MatrixXd> v) const;
  // The base's KKT system (equilibrated, LU) solved in place for the columns of v.
  void base_solve(Eigen::Ref<Eigen::MatrixXd> v) const;
  // The current free set is the base's (no border).
  void current_is_base();
  // Frees held variables until the free columns of C span what all columns span, so that the
  // working set (held bounds and the rows of C) is linearly independent: its multipliers are
  // then unique, and a released bound moves its variable off the bound.
  void free_a_basis();
  // The rank of the rows of C, to free_a_basis's threshold.
  static int rank_of_rows(const Eigen::MatrixXd& C);
  // x_F and μ of the subproblem with x_W held; x is updated only on the free entries.
  void solve_subproblem(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& x_free,
                        Eigen::VectorXd& mu) const;
  // Factorises the working set's free set unless the kept factorisation is of the same one;
  // false when singular.
  bool refactorise(DenseQpResult& out);
  // The size of x and the subproblem's solution x_free in the equilibrated unknowns (x_j / S_j over
  // the free variables): S_j times it is variable j's own scale, for round-off tests.
  double scaled_size(const Eigen::VectorXd& x, const Eigen::VectorXd& x_free) const;
  // Whether the free variables of a subproblem's solution lie within their bounds.
  bool feasible(const Eigen::VectorXd& l, const Eigen::VectorXd& u, const Eigen::VectorXd& x,
                const Eigen::VectorXd& x_free) const;
  // The warm start from working_ (see the file comment); true when it ends at a subproblem's
  // feasible solution, which x then holds.
  bool warm_start(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u, Eigen::VectorXd& x,
                  Eigen::VectorXd& x_free, Eigen::VectorXd& mu, DenseQpResult& out);
  // Moves x towards the subproblem's solution x_free as far as the bounds allow; true when a
  // bound blocked the step (its variable joins the working set).
  bool step_towards(const Eigen::VectorXd& l, const Eigen::VectorXd& u, const Eigen::VectorXd& x_free,
                    Eigen::VectorXd& x);
  // At a subproblem's solution: the multipliers ν of the held bounds into nu, and the held bound
  // whose multiplier has the wrong sign by the most beyond round-off (−1: none, x is optimal).
  int bound_to_release(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                       const Eigen::VectorXd& x, const Eigen::VectorXd& mu, Eigen::VectorXd& nu) const;

  const Eigen::MatrixXd& A_;
  const Eigen::MatrixXd& C_;
  const Updates updates_;
  const int C_rank_;  // the rank of C (rank_of_rows): what a working set's free columns must span
  // free_a_basis's workspace: an orthonormal basis of the free columns' span and one column.
  Eigen::MatrixXd basis_Q_;
  Eigen::VectorXd basis_v_, basis_w_;
  Eigen::MatrixXd basis_CF_, basis_gram_;  // the free columns of C, their Gram matrix
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> basis_eigen_;
  std::vector<Bound> working_;  // the working set of the current free set
  // The current free set: its variables, the independent rows of C over them, which of them
  // those rows pin (fixed by C: they cannot move), and their scales 1/√A_jj.
  std::vector<int> free_, kept_rows_;
  std::vector<char> pinned_;
  Eigen::VectorXd free_scale_;
  // The base: the free set whose KKT system is factorised, with its rows and pinned variables.
  std::vector<int> base_free_, base_rows_;
  std::vector<char> base_pinned_;
  std::vector<int> base_index_;  // per variable: its index in base_free_, −1 where not in it
  Eigen::MatrixXd kkt_;          // LU factors of S K S in place (unit lower, upper)
  Eigen::VectorXd kkt_scale_;    // S, the equilibration of the KKT system (factorise)
  std::vector<int> pivot_;
  long base_generation_ = 0;
  double base_pivot_ratio_ = 0;  // the base LU's smallest pivot over its largest entry
  // The border of the current free set on the base: per variable freed (added) or held (its
  // base column then held by a unit row), its scale, and the columns B̂ and Ẑ = K̂⁻¹B̂ of the
  // equilibrated bordered system [K̂ B̂; B̂ᵀ D̂]; the LU of its Schur complement D̂ − B̂ᵀẐ.
  std::vector<int> border_;
  std::vector<char> border_added_;
  Eigen::VectorXd border_scale_;
  Eigen::MatrixXd border_B_, border_Z_;
  Eigen::FullPivLU<Eigen::MatrixXd> schur_;
  // Per current free variable (free_'s order): its index among the bordered unknowns.
  std::vector<int> position_;
  mutable Eigen::MatrixXd rhs_;            // the subproblem's right-hand side, kept between calls
  bool factorised_ = false;                // the base is a valid factorisation
  long generation_ = 0, generations_ = 0;  // the current free set's number; how many were made
  // Recent factorisations besides the kept one, each with the free set it is of: a material
  // point of a structure returns to its own free set after its neighbour's, so one evaluator for
  // many points refactorised at nearly every point (38 % of a 128 × 16 beam's time). As many as
  // fit in kept_bytes (none for a large cell: its factors are large and its solves rare).
  struct Kept {  // a base
    std::vector<int> free, kept_rows, pivot;
    std::vector<char> pinned;
    Eigen::MatrixXd kkt;
    Eigen::VectorXd kkt_scale;
    long generation = 0, last_used = 0;
    double pivot_ratio = 0;
  };
  static constexpr std::size_t kept_bytes = 1 << 20, max_kept = 16;
  std::vector<Kept> kept_;
  long uses_ = 0;
  // Swaps the base with the entry of kept_ of free set `free`, which becomes the current free set
  // (true; false where there is none).
  bool take_kept(const std::vector<int>& free);
  // Stores the base in kept_ (in place of the least recently used entry when full).
  void store_base();
  void swap_base(Kept& e);
  std::vector<int> next_free_;  // refactorise's free set, kept between calls
};

}  // namespace dualcell::qp
