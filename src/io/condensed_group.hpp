#pragma once
// The exact law of a cell (law/condensed.hpp) as an HDF5 group, the same in sweep.h5 (/cell) and
// law.h5 (/law/cell); a dataset per member of law::for_each_member (law/condensed_members.hpp),
// and `bytes`; layout in docs/reference/sweep-h5.md ("/cell"):
//   n_macro, n_pairs (int), volume, reciprocity_error, seconds (1 each), operator_applications (int);
//   S0 (m×m), Y (n×m), H (n×n), G (k×n), row-major;
//   tangential, pair (n, int), lower_bonded, upper_bonded, lower_broken, upper_broken (n);
//   bonded (n_pairs, int 0/1): the bond state of the unloaded cell.
#include <string>

#include "io/hdf5.hpp"
#include "law/condensed.hpp"

namespace dualcell::io {

void write_condensed(File& f, const std::string& group, const law::CondensedCell& cell);
// Refuses a group that is incomplete, mis-shaped or inconsistent (law::consistency_problem),
// naming the file and the object.
law::CondensedCell read_condensed(const File& f, const std::string& group);

}  // namespace dualcell::io
