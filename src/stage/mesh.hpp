#pragma once
// The mesh stage as one call (dualcell-mesh): a scene to mesh.h5 (+ mesh.xdmf), and its summary.
#include <filesystem>

#include "mesh/mesh.hpp"
#include "rve/mesher.hpp"

namespace dualcell::stage {

// Reads and validates the scene (its warnings on stderr), checks the outputs before any work,
// builds the mapped mesh (a block of cells) or the gmsh mesh (an RVE, what the mesher did in
// `report`) and writes mesh.h5 with mesh.xdmf beside it, atomically.
mesh::Mesh run_mesh(const std::filesystem::path& scene_file, const std::filesystem::path& out,
                    rve::MeshReport* report = nullptr);
// dualcell-mesh's summary on stdout: cells (or the RVE's fibres and their statistics),
// subdomains, nodes, triangles, pairs, minimum angle.
void print_mesh_summary(const std::filesystem::path& scene_file, const std::filesystem::path& out,
                        const mesh::Mesh& mesh, const rve::MeshReport& report = {});

}  // namespace dualcell::stage
