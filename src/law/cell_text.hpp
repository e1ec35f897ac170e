#pragma once
// The exact law of a cell (law/condensed.hpp) as a plain text file, for codes that cannot read
// HDF5: the user material in CalculiX reads it (src/umat/cell_umat.hpp), `dualcell-export
// --format umat --form cell` writes it. Layout (docs/reference/cell-text.md): a first line
// "dualcell cell law 1", then one keyword per line followed by its numbers, whitespace
// separated, matrices row by row, doubles with 17 significant digits (so that the file gives
// the same law bit for bit), infinite bounds as "inf" / "-inf"; the keywords are the members of
// law::for_each_member (law/condensed_members.hpp) in its order, but for what the condensation
// measured:
//
//   n_macro m | volume |Ω| | rows n | pairs P | fibre_modes k
//   S0 (m·m) | Y (n·m) | H (n·n) | G (k·n)
//   tangential (n, 0/1) | pair (n) | lower_bonded, upper_bonded, lower_broken, upper_broken (n each)
//   bonded (P, 0/1)
#include <cstdint>
#include <iosfwd>
#include <string>

#include "law/condensed.hpp"

namespace dualcell::law {

void write_cell_text(std::ostream& out, const CondensedCell& cell);

// The cell of a file written by write_cell_text; `error` is set (and an empty cell returned)
// when the text is not one: what is wrong and where (the keyword).
CondensedCell read_cell_text(std::istream& in, std::string& error);

// The largest text write_cell_text writes for a cell within the limits (every extent at its
// extent_limit, every number at its longest, "-2.2250738585072014e-308"): a reader refuses a
// larger file from its size, before reading a byte of it (about 900 MB at 3 000 rows).
std::uintmax_t max_cell_text_bytes();

}  // namespace dualcell::law
