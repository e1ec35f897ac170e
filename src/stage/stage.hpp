#pragma once
// The stages as library calls: what each executable in src/apps does between parsing its
// options and printing its summary, so that a main() is options, one call and the summary.
// This header: the shape every stage's main() shares, run the stage's call and turn any
// exception into one line on stderr ("<stage>: error: <what>") and a non-zero exit; and the
// inputs that dualcell-solve and dualcell-sweep share (a scene and the mesh made from it).
#include <functional>
#include <string>

#include "core/exit_codes.hpp"
#include "core/scene.hpp"
#include "mesh/mesh.hpp"

namespace dualcell {

// Whether a stage shares its work over the ranks of an MPI launch (docs/method.md §16):
// dualcell-solve and dualcell-sweep do; the others, started under mpirun, run once, on rank 0,
// while the other ranks exit at once.
enum class Ranks { share, rank0_only };

int run_stage(const char* stage, const std::function<void()>& body, Ranks sharing = Ranks::rank0_only);

namespace stage {

// Prints the scene's warnings (e.g. near-incompressible materials) as "<stage>: warning: ...".
void print_warnings(const char* stage, const Scene& scene);

// A scene and the mesh made from it, checked to be of the same geometry (otherwise an
// InputError naming the key that differs), with the mesh file's content hash for provenance.
struct SceneAndMesh {
  Scene scene;
  mesh::Mesh mesh;
  std::string mesh_file, mesh_hash;
};
SceneAndMesh load_scene_and_mesh(const char* stage, const std::string& scene_file, const std::string& mesh_file);

}  // namespace stage

}  // namespace dualcell
