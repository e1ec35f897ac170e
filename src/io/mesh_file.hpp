#pragma once
// mesh.h5: the mesh stage's output and every later stage's input. Layout in
// docs/reference/mesh-h5.md; reading checks every dataset's presence and shape and the cross-references
// (node indices in range, subdomain ranges contiguous), so a corrupt file is refused at once.
#include <filesystem>
#include <string>

#include "core/scene.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::io {

// Writes mesh.h5 and mesh.xdmf (same stem) atomically: both appear complete or not at all.
void write_mesh(const mesh::Mesh& mesh, const Scene& scene, const std::filesystem::path& h5);

struct MeshFile {
  mesh::Mesh mesh;
  std::string scene_text;  // the scene the mesh was made from
};
MeshFile read_mesh(const std::filesystem::path& h5);

// Empty when the mesh was made from the same geometry as `scene`; otherwise one line saying
// which key differs (e.g. "[geometry] degree: mesh 2, scene 3").
std::string geometry_mismatch(const mesh::Mesh& mesh, const Scene& scene);

}  // namespace dualcell::io
