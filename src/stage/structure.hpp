#pragma once
// The structure stage as one call (dualcell-structure): a structure scene and a law.h5 to
// structure.h5 (+ XDMF), every load step with the fuse.
#include <filesystem>
#include <vector>

#include "structure/structure.hpp"

namespace dualcell::stage {

struct StructureOptions {
  std::filesystem::path scene_file, law_file, out;
  bool progress = true;  // one line per load step on stderr
};

struct StructureSummary {
  std::vector<structure::StepResult> steps;
  int n_nodes = 0, n_triangles = 0, fused_cells = 0, n_cells = 0;
  double cell_size = 0, seconds = 0;
  double first_fuse_factor = 0;  // structure::HomogenisedStructure::first_fuse_factor
  std::string fuse_note;         // why cells cannot fuse, when they cannot
};

// The cell law of a law.h5 for a structure: the bonded cone-wise law, the law past the fuse and
// the onset surface. Without a law past the fuse or an onset surface the cells keep the bonded
// law (`note` says why). Refuses a law.h5 without a fitted cone-wise law.
structure::CellLaw cell_law(const std::filesystem::path& law_file, double& cell_size, std::string& note);

StructureSummary run_structure(const StructureOptions& options);

}  // namespace dualcell::stage
