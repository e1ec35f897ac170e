#pragma once
// The members of law::CondensedCell, listed once (docs/architecture.md, "member tables"): every
// writer, reader and checker of the cell walks this list — bytes(), consistency_problem(), the
// HDF5 group (io/condensed_group.cpp), the cell's text (law/cell_text.cpp) and the JSON export
// (io/law_export.cpp). A new member of the cell is one line in for_each_member.
#include <Eigen/Core>
#include <concepts>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "law/condensed.hpp"

namespace dualcell::law {

// The sizes of the cell's arrays: one (a scalar), m = n_macro, n = n_rows(), P = n_pairs,
// k = G.rows(), which only G has (free), L = longitudinal (0 or 1: the ε33 column), and the
// longitudinal shear's: its macro shears (shear: 0 or 2), its rows (shear_rows)
// and Gz's rows (shear_modes, free as G's), T = thermal (0 or 1: the ΔT column). An extent of
// the optional parts (longitudinal, shear, shear_rows, thermal) may be 0: its members are then
// left out of the files (left_out).
enum class Extent { one, macro, rows, pairs, fibre_modes, longitudinal, shear, shear_rows, shear_modes, thermal };
inline constexpr int n_extents = 10;

// What a member's values must satisfy besides their shape (consistency_problem). The matrix
// rules include the ones before them: symmetric is finite too.
enum class Values {
  any,
  positive,                     // a scalar > 0, finite
  finite,                       // every entry
  symmetric,                    // finite and symmetric
  symmetric_positive_definite,  // and positive definite
  zero_one,                     // a flag per entry
  pair_index,                   // 0 … n_pairs − 1 per entry
  at_most_zero,                 // a lower bound per row, not NaN: the bounds hold p = 0
  at_least_zero,                // an upper bound per row, not NaN
};

struct Member {
  const char* name;  // in law.h5 and sweep.h5 (/cell/<name>) and the JSON; the cell's text keyword
  Extent rows = Extent::one, cols = Extent::one;  // the shape; a list (std::vector, VectorXd): rows
  Values values = Values::any;
  // Counts: the range they must lie in, and the extent they are (n_macro is m). An extent's
  // range is that of its count (rows, pairs and fibre modes: at most max_cell_rows).
  long lo = 0, hi = std::numeric_limits<long>::max();
  Extent sizes = Extent::one;
  // The keyword in the cell's text when it differs from name; what the condensation measured is
  // not in the text (the evaluation does not need it): `measured`.
  const char* text = nullptr;
  bool measured = false;
  // A count that an older law.h5 or sweep.h5 does not have: read as 0 there, and the arrays of
  // its extent as empty.
  bool optional = false;
};

// A size that the cell's text states before its arrays (law.h5 and the JSON have it in the
// shapes): not a member of the cell, the extent member.sizes of the cell as it stands.
struct TextSize {};

// Calls visit(member, value) for every member of the cell in the order of the files (the
// cell's text reads them in this order), value a reference into `cell` (const when cell is),
// or TextSize{} for a size of the text only.
template <class Cell, class Visit>
requires std::same_as<std::remove_const_t<Cell>, CondensedCell>
void for_each_member(Cell& cell, Visit&& visit) {
  using enum Extent;
  visit(Member{.name = "n_macro", .lo = 2, .hi = 3, .sizes = macro}, cell.n_macro);
  visit(Member{.name = "volume", .values = Values::positive}, cell.volume);
  visit(Member{.name = "rows", .hi = max_cell_rows, .sizes = rows}, TextSize{});
  visit(Member{.name = "n_pairs", .hi = max_cell_rows, .sizes = pairs, .text = "pairs"}, cell.n_pairs);
  visit(Member{.name = "fibre_modes", .hi = max_cell_rows, .sizes = fibre_modes}, TextSize{});
  visit(Member{.name = "S0", .rows = macro, .cols = macro, .values = Values::symmetric_positive_definite}, cell.S0);
  visit(Member{.name = "Y", .rows = rows, .cols = macro, .values = Values::finite}, cell.Y);
  visit(Member{.name = "H", .rows = rows, .cols = rows, .values = Values::symmetric}, cell.H);
  visit(Member{.name = "G", .rows = fibre_modes, .cols = rows, .values = Values::finite}, cell.G);
  visit(Member{.name = "tangential", .rows = rows, .values = Values::zero_one}, cell.tangential);
  visit(Member{.name = "pair", .rows = rows, .values = Values::pair_index}, cell.pair);
  visit(Member{.name = "lower_bonded", .rows = rows, .values = Values::at_most_zero}, cell.lower_bonded);
  visit(Member{.name = "upper_bonded", .rows = rows, .values = Values::at_least_zero}, cell.upper_bonded);
  visit(Member{.name = "lower_broken", .rows = rows, .values = Values::at_most_zero}, cell.lower_broken);
  visit(Member{.name = "upper_broken", .rows = rows, .values = Values::at_least_zero}, cell.upper_broken);
  visit(Member{.name = "bonded", .rows = pairs, .values = Values::zero_one}, cell.bonded);
  visit(Member{.name = "longitudinal", .hi = 1, .sizes = longitudinal, .optional = true}, cell.longitudinal);
  visit(Member{.name = "A33", .rows = macro, .cols = longitudinal, .values = Values::finite}, cell.A33);
  visit(Member{.name = "C33", .rows = longitudinal, .cols = longitudinal, .values = Values::finite}, cell.C33);
  visit(Member{.name = "y33", .rows = rows, .cols = longitudinal, .values = Values::finite}, cell.y33);
  visit(Member{.name = "shear", .hi = 2, .sizes = shear, .optional = true}, cell.shear);
  visit(Member{.name = "shear_rows", .hi = max_cell_rows, .sizes = shear_rows, .optional = true}, cell.shear_rows);
  visit(Member{.name = "shear_modes", .hi = max_cell_rows, .sizes = shear_modes}, TextSize{});
  visit(Member{.name = "D0z", .rows = shear, .cols = shear, .values = Values::symmetric_positive_definite}, cell.D0z);
  visit(Member{.name = "Yz", .rows = shear_rows, .cols = shear, .values = Values::finite}, cell.Yz);
  visit(Member{.name = "Hz", .rows = shear_rows, .cols = shear_rows, .values = Values::symmetric}, cell.Hz);
  visit(Member{.name = "Gz", .rows = shear_modes, .cols = shear_rows, .values = Values::finite}, cell.Gz);
  visit(Member{.name = "strength_z", .rows = shear_rows, .values = Values::at_least_zero}, cell.strength_z);
  visit(Member{.name = "pair_z", .rows = shear_rows, .values = Values::pair_index}, cell.pair_z);
  visit(Member{.name = "thermal", .hi = 1, .sizes = thermal, .optional = true}, cell.thermal);
  visit(Member{.name = "AT", .rows = macro, .cols = thermal, .values = Values::finite}, cell.AT);
  visit(Member{.name = "CT", .rows = longitudinal, .cols = thermal, .values = Values::finite}, cell.CT);
  visit(Member{.name = "yT", .rows = rows, .cols = thermal, .values = Values::finite}, cell.yT);
  visit(Member{.name = "reciprocity_error", .measured = true}, cell.reciprocity_error);
  visit(Member{.name = "seconds", .measured = true}, cell.seconds);
  visit(Member{.name = "operator_applications", .measured = true}, cell.operator_applications);
}

// The kinds of value a visitor meets: a count (int, long), a real, an array of reals (a matrix,
// a vector: Eigen), a list of integers (std::vector).
template <class T>
concept CountMember = std::integral<std::remove_cvref_t<T>>;
template <class T>
concept RealMember = std::same_as < std::remove_cvref_t<T>,
double > ;
template <class T>
concept ArrayMember = std::derived_from<std::remove_cvref_t<T>, Eigen::MatrixBase<std::remove_cvref_t<T>>>;
template <class T>
concept ListMember = std::same_as<std::remove_cvref_t<T>, std::vector<std::uint8_t>> ||
    std::same_as<std::remove_cvref_t<T>, std::vector<int>>;

// What is wrong with a cell: the member it is in (empty: the cell as a whole, or several members
// together) and what. consistency_problem is its text.
struct CellProblem {
  std::string member, what;
};
std::optional<CellProblem> find_problem(const CondensedCell& cell);

// Whether the files leave member m of the cell out: it has an extent of an optional part
// (longitudinal, shear, shear_rows) that is 0 for this cell, the count itself included. A file
// without them reads as a cell without that part; h5diff cannot compare empty arrays.
bool left_out(const CondensedCell& cell, const Member& m);
// Whether an extent belongs to an optional part (may be 0, its arrays then empty of any shape).
bool optional_extent(Extent e);
// Whether a member is of the longitudinal shear (the cell's text has it from version 3 on).
bool of_shear(const Member& m);
// Whether a member is of the temperature change (the cell's text has it from version 5 on).
bool of_thermal(const Member& m);

// The largest value an extent may take (rows, pairs, fibre modes: max_cell_rows; n_macro: 3;
// longitudinal, thermal: 1; shear: 2).
long extent_limit(Extent e);
// The value of an extent for the cell as it stands (fibre_modes: G's rows).
long extent(const CondensedCell& cell, Extent e);
// "n_macro", "n_rows", "n_pairs", "fibre_modes": how messages name an extent.
const char* extent_name(Extent e);

}  // namespace dualcell::law
