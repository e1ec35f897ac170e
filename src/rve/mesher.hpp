#pragma once
// The mesh of a periodic RVE (docs/method.md §16b): the rectangle Lx × Ly with its fibres (a
// list, checked, or random, generated: rve/microstructure.hpp), meshed by gmsh and split into
// subdomains, in the form the solver takes from the mapped mesher (mesh/mesh.hpp).
//
//   * Geometry: the rectangle and every fibre's periodic images that reach into it, fragmented
//     by OpenCASCADE into the matrix and the fibre pieces (a fibre crossing an edge is one piece
//     per side it reaches, each with the centre of its own image); right and top edges meshed as
//     copies of the left and bottom ones (matching nodes for the periodic rows).
//   * Size: element edge h = π r̄ / (4 degree) (a mapped cell's rim, r̄ the mean radius), finer
//     where fibres come close: at a point whose two nearest fibre surfaces are d₁ and d₂ away the
//     size is min(h, max(d₁ + d₂, h/10)), so a narrow gap has elements about as wide as it.
//     Frontal-Delaunay triangles; for p2 the mid-side nodes of the rims lie on the exact circles.
//   * Subdomains: every fibre piece one subdomain; the matrix whole ([solver] subdomain_dofs = 0,
//     the default) or split by METIS into parts of about subdomain_dofs DOFs (each connected part
//     a subdomain). Every subdomain has its own
//     nodes: interface pairs (fibre node, matrix node) where a fibre meets the matrix, glue pairs
//     where two matrix subdomains meet (at a node shared by m of them, m − 1 pairs from the first,
//     so that the gluing rows stay independent).
#include <string>

#include "core/scene.hpp"
#include "mesh/mesh.hpp"
#include "rve/microstructure.hpp"

namespace dualcell::rve {

// What the mesher did, for the mesh stage's summary.
struct MeshReport {
  Statistics fibres;        // of the microstructure meshed
  int fibre_pieces = 0;     // fibre subdomains (a fibre crossing an edge counts once per piece)
  int matrix_parts = 0;     // matrix subdomains
  double element_size = 0;  // h
  double seconds_gmsh = 0, seconds_split = 0;
};

// The mesh of an RVE geometry (geometry.rve()); subdomain_dofs as above. An InputError naming
// `where` for fibres that cannot be meshed or a gmsh failure (nothing is kept of gmsh's state).
mesh::Mesh build_rve_mesh(const Geometry& geometry, int subdomain_dofs, const std::string& where,
                          MeshReport* report = nullptr);

}  // namespace dualcell::rve
