#pragma once
// sweep.h5 (layout in docs/reference/sweep-h5.md) and its journal: every finished path is written
// at once to <out>.parts/path-NNN.h5 (temporary + rename), so that after an interruption,
// even kill -9, the same command skips the finished paths and the final file, assembled from
// the parts and renamed into place at the end, holds the same data as an uninterrupted run.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/fields.hpp"
#include "core/provenance.hpp"
#include "core/scene.hpp"
#include "law/onset.hpp"
#include "sweep/sweep.hpp"

namespace dualcell::io {

// The root of sweep.h5 besides its paths: where it came from and what the fit and the exports
// need of the scene.
// The header is sweep::SweepHeader (root attributes fibre_E, ..., and /onset in the file).
using sweep::SweepHeader;
// Identifies the inputs of a run (scene, material, mesh, solver options, code version): journal
// parts with another key are stale and recomputed.
std::string inputs_key(const SweepHeader& header);

// One column of /paths/NNN: a member of sweep::Step per row (exactly one member pointer set).
inline constexpr Field<sweep::Step, double, Eigen::Vector3d, long, bool> step_columns[] = {
    {"load", &sweep::Step::load},
    {"stress", &sweep::Step::stress},
    {"strain", &sweep::Step::strain},
    {"broken_bonds", &sweep::Step::broken_bonds},
    {"outer_iterations", &sweep::Step::outer_iterations},
    {"operator_applications", &sweep::Step::operator_applications},
    {"converged", &sweep::Step::converged},
    {"kkt_residual", &sweep::Step::kkt_residual},
    {"seconds", &sweep::Step::seconds},
};

// The objects of /paths/NNN/fuse: shape (1) loads and shape (3) strains.
inline constexpr Field<sweep::Fuse, double, Eigen::Vector3d> fuse_fields[] = {
    {"onset_load", &sweep::Fuse::onset_load},     {"load_before", &sweep::Fuse::load_before},
    {"load_after", &sweep::Fuse::load_after},     {"strain_before", &sweep::Fuse::strain_before},
    {"strain_after", &sweep::Fuse::strain_after},
};

std::filesystem::path parts_folder(const std::filesystem::path& out);
void write_part(const std::filesystem::path& out, const sweep::PathResult& path, const SweepHeader& header);
// The finished part of path `index`, if present and made from the same inputs.
std::optional<sweep::PathResult> read_part(const std::filesystem::path& out, int index, const SweepHeader& header);
// Writes the final file atomically and removes the parts.
void write_sweep(const std::filesystem::path& out, const std::vector<sweep::PathResult>& paths,
                 const SweepHeader& header);
// Reads every path of a sweep file (for the fit stage and tests); refuses foreign, truncated or
// incomplete files with one line naming the file and the object.
std::vector<sweep::PathResult> read_sweep(const std::filesystem::path& file);
// The root attributes of a sweep file.
SweepHeader read_sweep_header(const std::filesystem::path& file);

}  // namespace dualcell::io
