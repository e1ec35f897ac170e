#pragma once
// law.h5: the effective law of a cell block as it leaves the fit stage (layout in
// docs/reference/law-h5.md). One group /law holds every field of Law under its own name: per-direction
// datasets of D entries, the two 3×3 compliances with their standard errors and quality, the
// cone-wise linear form, and the constituents as attributes; the root holds the format and the
// provenance (io/file_root.hpp).
#include <filesystem>

#include "law/law.hpp"

namespace dualcell::io {

// Writes atomically (temporary + rename). A Law whose sizes disagree (no direction, or a
// direction_residual not of one entry per direction) is a bug of the caller:
// std::invalid_argument.
void write_law(const std::filesystem::path& file, const law::Law& law);

// Reads every field back. A missing, foreign, truncated or incomplete file, or an object of the
// wrong shape, is an InputError of one line naming the file, the object and what is wrong.
law::Law read_law(const std::filesystem::path& file);

}  // namespace dualcell::io
