#pragma once
// structure.h5 (layout in README.md, "structure.h5") and its XDMF companion: the mesh of a
// structure of homogeneous cells and, per load step, displacements, element stresses, open
// planes and fuse states, with the step's Newton report and reactions. Written atomically.
#include <filesystem>
#include <string>
#include <vector>

#include "core/provenance.hpp"
#include "structure/structure.hpp"

namespace dualcell::io {

void write_structure(const std::filesystem::path& out, const structure::StructureMesh& mesh,
                     const std::vector<structure::StepResult>& steps, double first_fuse_factor,
                     const std::string& law_form, const std::string& bond_unit, const Provenance& provenance);

}  // namespace dualcell::io
