#pragma once
// Where a result came from: the texts every output file carries as root attributes, so that a
// file read years later says which scene, material, mesh, sweep and code made it. One struct for
// every stage's files; io::write_provenance writes it, io::read_provenance reads it back.
#include <string>

#include "core/fields.hpp"
#include "core/version.hpp"

namespace dualcell {

struct Provenance {
  std::string scene_text;     // the scene file verbatim
  std::string scene_file;     // its path as given
  std::string material_text;  // the material file the scene named, verbatim (empty: inline tables)
  std::string mesh_file;      // the mesh a result was computed on, and its content hash
  std::string mesh_hash;
  std::string sweep_file;  // the sweep a law was fitted to, and its content hash
  std::string sweep_hash;
  std::string law_file;  // the law a structure was computed with, and its content hash
  std::string law_hash;
  std::string solver_options;                         // "key=value; ..." of [solver] and the fuse tolerance
  std::string code_version = dualcell::code_version;  // of the program that wrote the file
};

// The root attribute of each text (empty texts are not written).

inline constexpr Field<Provenance, std::string> provenance_fields[] = {
    {"scene", &Provenance::scene_text},          {"scene_file", &Provenance::scene_file},
    {"material", &Provenance::material_text},    {"mesh_file", &Provenance::mesh_file},
    {"mesh_hash", &Provenance::mesh_hash},       {"sweep_file", &Provenance::sweep_file},
    {"sweep_hash", &Provenance::sweep_hash},     {"law_file", &Provenance::law_file},
    {"law_hash", &Provenance::law_hash},         {"solver_options", &Provenance::solver_options},
    {"code_version", &Provenance::code_version},
};

}  // namespace dualcell
