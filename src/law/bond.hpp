#pragma once
// The bond rule of an interface row (docs/method.md §4, §11): the bounds ℓ ≤ p ≤ υ of its force
// per kind and bond state, when a bonded row is at its strength, and how much of its strength
// a force uses. The full solver (feti: the rows of B, the debond loop, the onset) and the exact
// law (law::CellEvaluator: its QP's bounds, its cascade, its onset) both ask here, so a new row
// kind or bond state is one edit in this file plus its physics.
//
//   kind       | intact (bonded)       | broken      | lifted (intact, strengths removed)
//   -----------+-----------------------+-------------+-----------------------------------
//   normal     | −s_n·L ≤ p < ∞        | 0 ≤ p < ∞   | −∞ < p < ∞ (0 ≤ p < ∞ when s_n = 0)
//   tangential | −s_t·L ≤ p ≤ s_t·L    | p = 0       | −∞ < p < ∞ (p = 0 when s_t = 0)
//
// p is the row's force (physical units: force per unit thickness), L the interface length of
// its pair, s_n and s_t the strengths per unit length. A row whose bounds are [0, 0] carries
// nothing: the full solver leaves it out (no tangential rows without adhesion), the exact law
// keeps it fixed at 0 so that its rows do not change with the bond state. Lifting keeps the
// response positively homogeneous in the load (what remains, p_n ≥ 0 where s_n = 0, is a cone),
// which is what the onset's scaling needs.
#include <cstdint>

namespace dualcell::law::bond {

enum class Kind : std::uint8_t { normal, tangential };
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
// pair's interface length L.
Bounds bounds(Kind kind, State state, double s_n, double s_t, double L);

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
// each is what the files have always held).
double reach(double p, Bounds intact);

// Whether a row that reaches its strength at load factor `row_reach` breaks at the onset s*
// (the least reach of all rows) as well, within at_strength_tolerance: a solve at exactly s*
// cannot tell such rows apart.
inline bool reaches_at_onset(double row_reach, double onset) {
  return row_reach <= onset * (1 + at_strength_tolerance);
}

}  // namespace dualcell::law::bond
