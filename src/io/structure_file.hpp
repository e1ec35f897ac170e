#pragma once
// structure.h5 (layout in docs/reference/structure-h5.md) and its XDMF companion: the mesh of a
// structure of homogeneous cells and, per load step, displacements, element stresses, open
// planes and fuse states, with the step's Newton report and reactions. Written atomically.
#include <filesystem>
#include <string>
#include <vector>

#include "core/provenance.hpp"
#include "structure/structure.hpp"

namespace dualcell::io {

// One column of /steps: a member of structure::StepResult per step (exactly one member pointer
// set); the writer walks it, and so does the test that reads the file back. The reactions (S×10)
// and the per-step fields in /steps/NNN are written beside them.
struct StructureStepColumn {
  const char* name;
  double structure::StepResult::*real = nullptr;             // float64, S
  Eigen::Vector2d structure::StepResult::*vector = nullptr;  // float64, S×2
  int structure::StepResult::*count = nullptr;               // int64, S
  bool structure::StepResult::*flag = nullptr;               // int64 0/1, S
};
inline const StructureStepColumn structure_step_columns[] = {
    {"factor", &structure::StepResult::factor},
    {"energy", &structure::StepResult::energy},
    {"energy_decrease", &structure::StepResult::energy_decrease},
    {"residual", &structure::StepResult::residual},
    {"watch_displacement", nullptr, &structure::StepResult::watch_displacement},
    {"newton_steps", nullptr, nullptr, &structure::StepResult::newton_steps},
    {"fuse_rounds", nullptr, nullptr, &structure::StepResult::fuse_rounds},
    {"newly_fused_cells", nullptr, nullptr, &structure::StepResult::newly_fused_cells},
    {"newly_broken", nullptr, nullptr, &structure::StepResult::newly_broken_units},
    {"open_triangles", nullptr, nullptr, &structure::StepResult::open_triangles},
    {"converged", nullptr, nullptr, nullptr, &structure::StepResult::converged},
};

void write_structure(const std::filesystem::path& out, const structure::StructureMesh& mesh,
                     const std::vector<structure::StepResult>& steps, double first_fuse_factor,
                     const std::string& law_form, const std::string& bond_unit, const Provenance& provenance);

}  // namespace dualcell::io
