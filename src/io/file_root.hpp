#pragma once
// What every dualcell file shares at its root: the attribute `format` naming the kind of file,
// checked by every reader in one place, and the provenance texts (core/provenance.hpp).
#include <initializer_list>

#include "core/provenance.hpp"
#include "core/scene.hpp"
#include "io/hdf5.hpp"

namespace dualcell::io {

// The formats the stages write (layouts in docs/reference/); law.h5's is law::format_name.
inline constexpr const char* mesh_format = "dualcell mesh 4";
inline constexpr const char* solution_format = "dualcell solution 2";
inline constexpr const char* sweep_format = "dualcell sweep 3";
inline constexpr const char* structure_format = "dualcell structure 1";

// Refuses a file whose root attribute `format` is not `format`, with one line:
// "<file>: not a dualcell law file (root attribute format is 'dualcell sweep 1', expected 'dualcell law 4')".
void check_format(const File& file, const char* format);

// Writes `format` and every non-empty provenance text as root attributes.
void write_provenance(File& file, const char* format, const Provenance& provenance);
// The provenance texts at the root; those named in `required` must be there (InputError
// otherwise), the others are empty when missing.
Provenance read_provenance(const File& file, std::initializer_list<const char*> required = {});

// The constituents as attributes of `object` (constituent_fields names), and back.
void write_constituents(File& file, const std::string& object, const Constituents& constituents);
Constituents read_constituents(const File& file, const std::string& object);

}  // namespace dualcell::io
