#pragma once
// The onset surface (law/onset.hpp) as an HDF5 group, the same in sweep.h5 (/onset) and law.h5
// (/law/onset); layout in docs/reference/sweep-h5.md and law-h5.md:
//   attributes linear (int 0/1), message (string);
//   facets (K×3), pair (K, int), tangential (K, int 0/1)          where linear;
//   path_stress (P×3), onset (P), sweep_onset (P)                 where checked against a sweep.
#include <string>

#include "io/hdf5.hpp"
#include "law/onset.hpp"

namespace dualcell::io {

void write_onset(File& f, const std::string& group, const law::OnsetSurface& surface);
// Refuses a group that is incomplete or out of range, naming the file and the object.
law::OnsetSurface read_onset(const File& f, const std::string& group);

}  // namespace dualcell::io
