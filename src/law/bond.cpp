#include "law/bond.hpp"

#include <cmath>
#include <limits>

namespace dualcell::law::bond {

namespace {
constexpr double inf = std::numeric_limits<double>::infinity();
}  // namespace

Bounds bounds(Kind kind, State state, double s_n, double s_t, double L) {
  if (state == State::lifted) return lifted(bounds(kind, State::intact, s_n, s_t, L));
  const bool intact = state == State::intact;
  switch (kind) {
    case Kind::normal:
      return {intact ? -s_n * L : 0.0, inf};
    case Kind::tangential:
    case Kind::along_fibres:
      return intact ? Bounds{-s_t * L, s_t * L} : Bounds{0.0, 0.0};
    case Kind::facet:
      return intact ? Bounds{-inf, 1.0} : Bounds{0.0, 0.0};
  }
  return {};
}

Bounds lifted(Bounds intact) { return {intact.lower < 0 ? -inf : intact.lower, intact.upper > 0 ? inf : intact.upper}; }

bool at_strength(double p, Bounds intact) {
  const double lo = intact.lower, hi = intact.upper;
  const bool at_lower = std::isfinite(lo) && lo < 0 && p <= lo + at_strength_tolerance * std::abs(lo);
  const bool at_upper = std::isfinite(hi) && hi > 0 && p >= hi - at_strength_tolerance * std::abs(hi);
  return at_lower || at_upper;
}

double strength_use(double p, Bounds intact) {
  if (p < 0 && std::isfinite(intact.lower) && intact.lower < 0) return p / intact.lower;
  if (p > 0 && std::isfinite(intact.upper) && intact.upper > 0) return p / intact.upper;
  return 0;
}

double reach(double p, Bounds intact, double p0) {
  const bool lower = std::isfinite(intact.lower) && intact.lower < 0;
  const bool upper = std::isfinite(intact.upper) && intact.upper > 0;
  if ((lower && p0 <= intact.lower) || (upper && p0 >= intact.upper)) return 0;
  if (p < 0 && lower) return (intact.lower - p0) / p;
  if (p > 0 && upper) return (intact.upper - p0) / p;
  return inf;
}

}  // namespace dualcell::law::bond
