#pragma once
// The contact/adhesion solver: one macroscopic stress σ̄ in, displacements, interface forces,
// macro strain and a KKT report out (docs/method.md §6–§12). Setup (assembly, K⁺ factorisations) is done
// once in the constructor and reused for every load case and bond state; the dual problem
// (B, G, GGᵀ) is rebuilt only when the bond state changes.
//
//   symbol | variable               | meaning
//   -------+------------------------+--------------------------------------------------
//   σ̄      | sigma                  | applied macro stress (σxx, σyy, σxy)
//   λ      | Solution::lambda       | interface/gluing forces per row of B (physical units)
//   α      | Solution::alpha        | rigid-body amplitudes per subdomain (u = K⁺(f−Bᵀλ) + Rα)
//   ε̄      | Solution::strain       | (1/|Ω|) ∮ sym(u ⊗ n) ds over the outer boundary
//   s*     | debond_onset()         | load factor at which the first bond reaches its strength
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "core/macro_state.hpp"
#include "feti/constraints.hpp"
#include "feti/dual.hpp"
#include "feti/setup.hpp"
#include "law/onset.hpp"
#include "law/ply.hpp"
#include "qp/result.hpp"

namespace dualcell::feti {

// KKT residuals of a solve, in physical units where stated (all should be ~0).
struct KktReport {
  double relative_projected_gradient = 0;  // SMALBE: ‖gᴾ‖/‖b‖ of the dual QP
  double relative_equality_residual = 0;   // ‖Gλ − e‖ / max(‖e‖, ‖G‖‖λ‖)
  double bound_violation = 0;              // max (ℓ−λ, λ−υ, 0), force units
  double complementarity = 0;  // max min(λ−ℓ, υ−λ, ‖λ‖∞)·|gap| over interface rows, force × length
  double max_penetration = 0;  // max (n·(u_f − u_m), 0), length units
  double max_glue_jump = 0;    // max |B u − c| over glue, Dirichlet, periodic rows, length
  double relative_equilibrium = 0;  // max_i ‖K_i u_i − f_i + B_iᵀλ‖∞ / ‖f‖∞
};

struct Timings {
  double assembly = 0, factorisation = 0;  // once per solver (setup)
  double explicit_operators = 0;           // K⁺(b, b) of the explicit subdomains, once per solver
  double dual_setup = 0;                   // B, G, GGᵀ for the bond states used
  double qp = 0, recovery = 0;
  // Inside qp: the applications of F, of the projector Q (coarse problem) and of the
  // preconditioner M⁻¹ (wall time, all threads; the rest of qp is the QP's vector work), and
  // over the ranks of a group (docs/method.md §16) this rank's seconds in the exchanges between
  // ranks, their number and the bytes received (0 alone).
  OperatorProfile in_qp;
  // Adds another QP's (qp_timing_fields and in_qp) to this one's.
  void add_qp(const Timings& other);
};
// Timings' seconds, listed once (core/fields.hpp): the solver's setup, once, and those a QP
// accumulates (Timings::add_qp); solution.h5 writes each as /solver seconds_<name>, and in_qp's as
// seconds_qp_<name>.
inline constexpr Field<Timings, double> setup_timing_fields[] = {
    {"assembly", &Timings::assembly, 0, "s"},
    {"factorisation", &Timings::factorisation, 0, "s"},
    {"explicit_operators", &Timings::explicit_operators, 0, "s"},
    {"dual_setup", &Timings::dual_setup, 0, "s"},
};
inline constexpr Field<Timings, double> qp_timing_fields[] = {
    {"qp", &Timings::qp, 0, "s"},
    {"recovery", &Timings::recovery, 0, "s"},
};
inline void Timings::add_qp(const Timings& other) {
  add_fields(qp_timing_fields, *this, other);
  in_qp += other.in_qp;
}

struct Solution {
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();           // applied (σxx, σyy, σxy)
  Eigen::Vector3d strain = Eigen::Vector3d::Zero();          // (εxx, εyy, εxy), tensor shear
  Eigen::Vector3d average_stress = Eigen::Vector3d::Zero();  // volume average of element stresses
  // Generalised plane strain (docs/method.md §3a): the longitudinal strain ε33 the solve had and
  // the volume average of σzz (plane strain, ε33 = 0: ν's share of the in-plane stresses).
  double eps33 = 0, average_stress_zz = 0;
  double delta_T = 0;  // the temperature change it was solved at (fem::Uniform)
  // With shears Γ = (γxz, γyz) along the fibres (a macro state holding them, ContactSolver::solve): Γ and the
  // average shear stress ⟨τ⟩ = (τxz, τyz) of the final bond state; zero (Γ) and NaN (τ) without.
  Eigen::Vector2d gamma = Eigen::Vector2d::Zero();
  Eigen::Vector2d shear_stress = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::VectorXd u;                                   // global DOFs (+3 macro DOFs εxx, εyy, γxy when periodic)
  Eigen::VectorXd lambda;                              // per row of B, physical (force) units
  Eigen::VectorXd multiplier;                          // SMALBE's equality multiplier m (scaled rows), for warm starts
  Eigen::VectorXd alpha;                               // 3 per subdomain
  std::vector<double> normal_force, tangential_force;  // per interface pair (0 where no row)
  BondState bonds;                                     // after this solve (and its breaks)
  long newly_broken = 0;                               // bonds broken by this solve's debonding loop
  long debond_rounds = 0;                              // QP solves in the debonding loop
  long n_rows = 0;                                     // dim λ of the last QP
  int subdomains = 0, explicit_subdomains = 0;         // (not the macro one) and how many apply F explicitly
  qp::Result qp;                                       // of the last QP
  // The QPs' counters over all QPs of this solve; operator_applications also counts the F
  // applications outside them (Fλ₀, the norm estimate), preconditioner_applications the M⁻¹ ones.
  qp::Counters counters;
  // Times the dual tolerance was tightened because a converged QP did not give the primal
  // accuracy the check asks (docs/method.md §10), and the dual tolerance of the last QP.
  long tightenings = 0;
  double qp_tolerance = 0;
  KktReport kkt;
  // The recovered primal solution, checked (not assumed): penetration and glue jumps within
  // primal_tolerance·‖u‖∞, complementarity within primal_tolerance·‖λ‖∞‖u‖∞.
  bool primal_ok = true;
  std::string primal_message;  // what failed, when !primal_ok
  Timings seconds;
  bool qp_converged() const { return qp.status == qp::Status::converged; }
  // Adds the work (counters, seconds but the setup's) of an earlier QP of the same load.
  void add_work(const Solution& earlier) {
    counters += earlier.counters;
    tightenings += earlier.tightenings;
    seconds.dual_setup += earlier.seconds.dual_setup;
    seconds.add_qp(earlier.seconds);
  }
  bool converged() const { return qp_converged() && primal_ok; }
};

class ContactSolver {
 public:
  // threads, min_dofs_per_thread: see FetiSetup (0 threads = all OpenMP offers); results do not
  // depend on them. group: the ranks that solve together, each owning some subdomains
  // (FetiSetup); every call below is then collective over the group, and every rank gets the
  // whole Solution.
  // progress, when given, shows the phase and every SMALBE outer iteration while it works (it
  // must outlive the solver). expected_qps: how many QPs the caller will solve (FetiSetup).
  ContactSolver(const mesh::Mesh& mesh, const Scene& scene, int threads = 1,
                int min_dofs_per_thread = FetiSetup::default_min_dofs_per_thread, par::Group group = {},
                Progress* progress = nullptr, double expected_qps = 1);
  // The cached dual problem refers to setup_: not copyable, not movable.
  ContactSolver(const ContactSolver&) = delete;
  ContactSolver& operator=(const ContactSolver&) = delete;

  // The macro state of a solve (core/macro_state.hpp): the in-plane macro stress σ̄ (stress-driven;
  // for boundary = "edges" the load factor (t, 0, 0) of the scene's loads), with what it holds:
  // a uniform strain ε33 along the fibres (generalised plane strain, docs/method.md §3a: each
  // subdomain's eigen-stress λ ε33 (1, 1, 0) in the load and in the stresses, σzz averaged into
  // Solution::average_stress_zz), and the shears Γ = (γxz, γyz) along them (a periodic cell with
  // [load] macro = "full", §16a: solve() runs the antiplane one-body solve of each round's bond
  // state beside the QP, primal::longitudinal_shear_at, each tie bounded by its strength s_t L,
  // and a pair whose tie reaches it breaks as a whole with the in-plane breaks of that round, as
  // the exact law's cascade does; ⟨τ⟩ in Solution::shear_stress; std::invalid_argument for another
  // scene). Nothing held, the default, is plane strain, every result as before bit for bit.
  //
  // One QP for a fixed bond state: no bond breaks even where a multiplier sits at its strength.
  // `warm_lambda` (physical) and `warm_multiplier` (SMALBE's m) of the same bond state start the
  // iteration; scaled to a new load they are the exact answer of a positively homogeneous
  // problem (no adhesion), so a proportional step costs almost nothing.
  Solution solve_fixed(const MacroState& state, const BondState& bonds, const Eigen::VectorXd* warm_lambda = nullptr,
                       const Eigen::VectorXd* warm_multiplier = nullptr);
  // Solve, break every bond at its strength (normal and tangential together), re-solve until
  // no new break (docs/method.md §11). `bonds` is the state before the load; the result carries the new one.
  Solution solve(const MacroState& state, const BondState& bonds, const Eigen::VectorXd* warm_lambda = nullptr,
                 const Eigen::VectorXd* warm_multiplier = nullptr);
  // The in-plane macro stress alone: MacroState::stress(sigma).
  Solution solve_fixed(const Eigen::Vector3d& sigma, const BondState& bonds,
                       const Eigen::VectorXd* warm_lambda = nullptr, const Eigen::VectorXd* warm_multiplier = nullptr) {
    return solve_fixed(MacroState::stress(sigma), bonds, warm_lambda, warm_multiplier);
  }
  Solution solve(const Eigen::Vector3d& sigma, const BondState& bonds, const Eigen::VectorXd* warm_lambda = nullptr,
                 const Eigen::VectorXd* warm_multiplier = nullptr) {
    return solve(MacroState::stress(sigma), bonds, warm_lambda, warm_multiplier);
  }

  // s* = min over bonded rows of bound/λ(σ̄): the load factor t at which the first bond of the
  // intact interface reaches its strength under t·σ̄ (docs/method.md §11), from one solve of the bonded
  // problem with the strength bounds lifted (what remains, λ_n ≥ 0 where s_n = 0, is a cone,
  // so the response is positively homogeneous in t). +inf without adhesion; NaN when that
  // solve did not converge. Scenes with adhesion have no body force (checked on reading).
  // `critical`, when given, receives the pairs whose bond reaches its strength at s* (within
  // the relative at-strength tolerance): a solve at exactly s*·σ̄ cannot tell them from the
  // QP's multipliers at the scene's tolerance, so a caller stepping onto the onset breaks them.
  // With the scene's temperature change ΔT (held along every path, docs/theory/model.md §1a) the
  // bonded forces are affine in t, p0 + t·p, and s* the least t ≥ 0 at which one reaches its
  // strength (0: the cool-down alone breaks it); an InputError where the lifted problem keeps
  // contact rows (then not affine). NaN when the thermal solve did not converge; onset_note then
  // says why (empty after an onset that is a number).
  double debond_onset(const Eigen::Vector3d& sigma, std::vector<int>* critical = nullptr);
  const std::string& onset_note() const { return onset_note_; }

  // The exact onset surface (law/onset.hpp): the bonded rows' forces per unit stress from
  // three unit solves (two on the symmetry boundary, which carries no shear), one facet per
  // strength bound. Not linear (no facets, `message` says why) without adhesion or when some
  // normal row has no normal strength and stays a contact row.
  law::OnsetSurface onset_surface();

  // The bonded cell's thermal expansion per kelvin (law::PlyExpansion): two solves of the bonded
  // problem with the strengths lifted, at the scene's tolerance. Empty (ok 0, no note) where the
  // phases have no expansion coefficients.
  law::PlyExpansion bonded_expansion();

  // The dual problems are cached: the intact bond state's, the last other one's and the onset's
  // (bonds lifted), each with its ‖PFP‖ estimate. Each is a function of its bond state alone
  // (the estimate starts from a fixed vector), so a path solved from the cache gives the bits
  // of one solved from scratch, and a resumed sweep repeats an uninterrupted one; a sweep's
  // paths then cost their QPs. forget_dual drops them (to time a cold solve).
  void forget_dual() {
    intact_ = {};
    other_ = {};
    lifted_ = {};
  }

  const FetiSetup& setup() const { return setup_; }
  const DualProblem& problem(const BondState& bonds);
  BondState intact() const { return intact_bonds(setup_.mesh(), setup_.scene().interface); }

 private:
  // One QP at the dual tolerance `qp_tolerance` (the scene's when ≤ 0); the primal check always
  // uses the scene's tolerance.
  Solution solve_problem(const DualProblem& problem, double norm_PFP, const MacroState& state,
                         const Eigen::VectorXd* warm_lambda, const Eigen::VectorXd* warm_multiplier = nullptr,
                         double qp_tolerance = 0);
  void recover(const DualProblem& problem, const Eigen::VectorXd& f, const Eigen::VectorXd& d,
               const Eigen::VectorXd& lambda_scaled, const Eigen::VectorXd& multiplier, Solution& out) const;
  void report(const DualProblem& problem, const Eigen::VectorXd& f, const Eigen::VectorXd& lambda_scaled,
              Solution& out) const;

  struct Cached {
    std::unique_ptr<DualProblem> dual;
    BondState bonds;
    double norm_PFP = 0;  // ‖PFP‖ of dual, estimated when it is built
  };
  Cached& cached(const BondState& bonds);
  // The bonded problem with the strengths lifted (debond_onset, onset_surface) and the bounds it
  // lifted; linear: whether every bonded row has a normal strength (lifted_bonded).
  struct Lifted : Cached {
    Eigen::VectorXd lower, upper;
    bool linear = false;
    // With the scene's temperature change ΔT: the rows' forces of ΔT alone (force units), the
    // affine part of every path's bonded forces p0 + t·p; empty without ΔT. `thermal_message`:
    // why there are none although ΔT ≠ 0 (the solve did not converge, or contact rows).
    Eigen::VectorXd thermal;
    std::string thermal_message;
  };
  Lifted& lifted();

  FetiSetup setup_;
  Progress* progress_ = nullptr;
  Cached intact_, other_;
  Lifted lifted_;
  std::string onset_note_;              // why the last debond_onset is NaN
  std::vector<double> shear_strength_;  // per pair, s_t L (shear_strengths), at the first solve with Γ
};

}  // namespace dualcell::feti
