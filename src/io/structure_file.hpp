#pragma once
// structure.h5 (layout in docs/reference/structure-h5.md) and its XDMF companion: the mesh of a
// structure of homogeneous cells and, per load step, displacements, element stresses, open
// planes and fuse states, with the step's Newton report and reactions. Written atomically.
#include <filesystem>
#include <string>
#include <vector>

#include "core/fields.hpp"
#include "core/provenance.hpp"
#include "structure/structure.hpp"

namespace dualcell::io {

// One column of /steps: a member of structure::StepResult per step (exactly one member pointer
// set); the writer walks it, and so does the test that reads the file back. The reactions (S×10)
// and the per-step fields in /steps/NNN are written beside them.
inline constexpr Field<structure::StepResult, double, Eigen::Vector2d, int, bool> structure_step_columns[] = {
    {"factor", &structure::StepResult::factor},
    {"energy", &structure::StepResult::energy},
    {"energy_decrease", &structure::StepResult::energy_decrease},
    {"residual", &structure::StepResult::residual},
    {"watch_displacement", &structure::StepResult::watch_displacement},
    {"newton_steps", &structure::StepResult::newton_steps},
    {"fuse_rounds", &structure::StepResult::fuse_rounds},
    {"newly_fused_cells", &structure::StepResult::newly_fused_cells},
    {"newly_broken", &structure::StepResult::newly_broken_units},
    {"open_triangles", &structure::StepResult::open_triangles},
    {"converged", &structure::StepResult::converged},
};

void write_structure(const std::filesystem::path& out, const structure::StructureMesh& mesh,
                     const std::vector<structure::StepResult>& steps, double first_fuse_factor,
                     const std::string& law_form, const std::string& bond_unit, const Provenance& provenance);

}  // namespace dualcell::io
