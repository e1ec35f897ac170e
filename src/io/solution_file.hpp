#pragma once
// solution.h5: the output of dualcell-solve (layout in README.md, "solution.h5"), with an
// XDMF beside it that shows the deformed shape, gaps included, in ParaView.
#include <filesystem>
#include <string>

#include "core/scene.hpp"
#include "feti/solver.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::io {

struct SolutionProvenance {
  std::string mesh_file;
  std::string mesh_hash;
};

void write_solution(const std::filesystem::path& h5, const mesh::Mesh& mesh, const Scene& scene,
                    const feti::Solution& solution, const SolutionProvenance& provenance);

// The bond state stored in a solution file (/interface/bonded), checked against the mesh: the
// file must have been solved on the mesh whose hash is `mesh_hash`.
feti::BondState read_bonds(const std::filesystem::path& h5, const mesh::Mesh& mesh, const std::string& mesh_hash);

}  // namespace dualcell::io
