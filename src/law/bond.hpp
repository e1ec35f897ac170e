#pragma once
// The bond rule of an interface row (docs/theory/homogenisation.md §11): the bounds ℓ ≤ p ≤ υ of
// its force per kind and bond state, when a bonded row is at its strength, how much of its
// strength a force uses, and the one debond cascade that breaks what is at its strength and
// solves again. The full solver (feti: the rows of B, the debond loop, the onset, the one-body
// cascade along z), the exact law (law::CellEvaluator: its QP's bounds, its cascade, its onset)
// and the compact cells built from it (the small cell's facet rows, a basis's contact rows) all
// ask here, so a new row kind or bond state is one edit in this file plus its physics.
//
//   kind         | intact (bonded)        | broken      | lifted (intact, strengths removed)
//   -------------+------------------------+-------------+-----------------------------------
//   normal       | −s_n·L ≤ p < ∞         | 0 ≤ p < ∞   | −∞ < p < ∞ (0 ≤ p < ∞ when s_n = 0)
//   tangential   | −s_t·L ≤ p ≤ s_t·L     | p = 0       | −∞ < p < ∞ (p = 0 when s_t = 0)
//   along_fibres | −s_t·L ≤ q ≤ s_t·L     | q = 0       | −∞ < q < ∞ (q = 0 when s_t = 0)
//   facet        | −∞ < g ≤ 1             | g = 0       | −∞ < g < ∞
//
// p is the row's force (physical units: force per unit thickness), L the interface length of
// its pair, s_n and s_t the strengths per unit length. q is a pair's force along the fibres (the
// shear along z, §16a): its tie holds the pair's tangential strength both ways. g is a row of a
// compact cell's onset polytope (docs/theory/exact-law.md, the small cell with a fuse): its
// force normalised by its strength, so that the row is at its strength exactly on its facet
// g = 1; past the fuse it carries nothing. A contact row without strength (a basis cell's rows,
// the normal rows where s_n = 0) is a normal row with s_n = 0: 0 ≤ p in every state.
// A row whose bounds are [0, 0] carries nothing: the full solver leaves it out (no tangential
// rows without adhesion), the exact law keeps it fixed at 0 so that its rows do not change with
// the bond state. Lifting keeps the response positively homogeneous in the load (what remains,
// p_n ≥ 0 where s_n = 0, is a cone), which is what the onset's scaling needs.
//
// Bounds that depend on the state. Each solve of the cascade below takes the bounds of the bond
// state the last round left, and each round asks which pairs the forces move to another state
// (today: intact → broken at the strength). A bound that depends on the forces, Coulomb
// friction |p_t| ≤ μ·p_n on a broken pair, is a state whose bounds take the pair's normal force
// and a move the round reports when that force has changed; the cascade then solves until no
// pair moves, the fixed point such a bound needs (docs/architecture.md, "a new row kind").
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dualcell::law::bond {

enum class Kind : std::uint8_t { normal, tangential, along_fibres, facet };
enum class State : std::uint8_t { intact, broken, lifted };

struct Bounds {
  double lower = 0, upper = 0;
  // [0, 0]: the row carries no force in this state.
  bool carries_force() const { return lower != 0 || upper != 0; }
};

// Relative distance within which a bonded force counts as "at its strength": far below any load
// step a sweep resolves (1e-3), far above the QPs' round-off at a bound (MPRGP and the dense
// active-set method put a component exactly on it).
inline constexpr double at_strength_tolerance = 1e-7;

// The bounds of a row of `kind` in `state`, for strengths s_n, s_t per unit length and the
// pair's interface length L (a facet row's strength is 1 by its normalisation: it takes none).
Bounds bounds(Kind kind, State state, double s_n, double s_t, double L);

// The intact bounds of a row along the fibres whose pair holds `strength` = s_t·L, the value the
// full solver (feti::shear_strengths) and the cell (CondensedCell::strength_z) keep per pair.
inline Bounds intact_along_fibres(double strength) { return {-strength, strength}; }

// The intact bounds with their strengths removed (the `lifted` column of the table, from the
// intact bounds alone: a strength bound goes to infinity, a contact bound at 0 stays).
Bounds lifted(Bounds intact);

// Whether a bonded row's force p is at (or past) one of its strength bounds, within
// at_strength_tolerance: the bond breaks.
bool at_strength(double p, Bounds intact);

// The fraction of its strength that the force p uses: p/ℓ below 0, p/υ above (0 where the side p
// lies on has no strength). 1 at the strength; along a load scaled by t (lifted bonds: p ∝ t) the
// row reaches its strength at t = 1/use.
double strength_use(double p, Bounds intact);

// The load factor at which a lifted row's force p (at load factor 1) reaches its intact strength
// bound: ℓ/p or υ/p, +inf where it never does; 1/strength_use up to one rounding (the full
// solver's onset takes the least reach, the exact law's 1/(the largest use): the rounding of
// each is what the files have always held). Along an affine load, the row's force p0 + t·p (p0:
// the force of a state held along the path, a cool-down's), the t ≥ 0 at which it reaches a
// bound: (ℓ − p0)/p or (υ − p0)/p; 0 where p0 is at or beyond a bound already. p0 = 0 gives ℓ/p,
// υ/p bit for bit.
double reach(double p, Bounds intact, double p0 = 0);

// Whether a row that reaches its strength at load factor `row_reach` breaks at the onset s*
// (the least reach of all rows) as well, within at_strength_tolerance: a solve at exactly s*
// cannot tell such rows apart.
inline bool reaches_at_onset(double row_reach, double onset) {
  return row_reach <= onset * (1 + at_strength_tolerance);
}

// How a cascade ended (cascade below).
struct CascadeEnd {
  int rounds = 0;        // solves run
  int newly_broken = 0;  // pairs that went from bonded to broken
  bool solved = true;    // false: a solve failed, the cascade stopped at it
  bool settled = true;   // false: after max_rounds solves the last still left pairs at their strength
};

// The debond cascade (§11), the one loop of the full solver, the exact law and the one-body solve
// along z: `solve()` runs one solve with the bonds of `bonded` (false when it failed: the cascade
// stops there); `at_strength(pairs)` appends the bonded pairs that solve left at their strength
// (a pair whose normal, tangential or along-z row is: the pair breaks as a whole, each pair once
// or more); they break, `next(pairs)` carries what the next solve starts from (a warm start), and
// the cascade solves again, until a solve breaks nothing or `max_rounds` solves have run (the
// last solve's pairs then stay bonded, `settled` false). `bonded` is indexed by pair, nonzero
// while bonded.
template <class Bonded, class Solve, class AtStrength, class Next>
CascadeEnd cascade(Bonded& bonded, int max_rounds, Solve&& solve, AtStrength&& at_strength, Next&& next) {
  CascadeEnd end;
  std::vector<int> breaking;
  for (;;) {
    ++end.rounds;
    if (!solve()) {
      end.solved = false;
      return end;
    }
    breaking.clear();
    at_strength(breaking);
    if (breaking.empty()) return end;
    if (end.rounds >= max_rounds) {
      end.settled = false;
      return end;
    }
    for (const int p : breaking) {
      auto& b = bonded[static_cast<std::size_t>(p)];
      end.newly_broken += b != 0 ? 1 : 0;
      b = 0;
    }
    next(breaking);
  }
}

}  // namespace dualcell::law::bond
