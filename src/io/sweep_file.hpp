#pragma once
// sweep.h5 (layout in README.md, "sweep.h5") and its journal: every finished path is written
// at once to <out>.parts/path-NNN.h5 (temporary + rename), so that after an interruption,
// even kill -9, the same command skips the finished paths and the final file, assembled from
// the parts and renamed into place at the end, holds the same data as an uninterrupted run.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sweep/sweep.hpp"

namespace dualcell::io {

struct SweepProvenance {
  std::string scene_text, material_text, scene_file;
  std::string mesh_file, mesh_hash;
  std::string solver_options;  // "key=value; ..." of [solver] and fuse_tolerance
  std::string code_version;
  // Constituents and fibre volume fraction π r²/a², for the fit and the exports.
  double fibre_E = 0, fibre_nu = 0, matrix_E = 0, matrix_nu = 0, fibre_volume_fraction = 0;
  // Identifies the inputs of a run: parts with another key are stale and recomputed.
  std::string key() const;
};

std::filesystem::path parts_folder(const std::filesystem::path& out);
void write_part(const std::filesystem::path& out, const sweep::PathResult& path, const SweepProvenance& provenance);
// The finished part of path `index`, if present and made from the same inputs.
std::optional<sweep::PathResult> read_part(const std::filesystem::path& out, int index,
                                           const SweepProvenance& provenance);
// Writes the final file atomically and removes the parts.
void write_sweep(const std::filesystem::path& out, const std::vector<sweep::PathResult>& paths,
                 const SweepProvenance& provenance);
// Reads every path of a sweep file (for the fit stage and tests); refuses foreign, truncated or
// incomplete files with one line naming the file and the object.
std::vector<sweep::PathResult> read_sweep(const std::filesystem::path& file);
// The root attributes of a sweep file.
SweepProvenance read_sweep_provenance(const std::filesystem::path& file);

}  // namespace dualcell::io
