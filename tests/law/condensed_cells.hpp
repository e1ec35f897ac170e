#pragma once
// Condensed cells the law's tests share: one periodic glass-like fibre (E_f/E_m = 30) in a mapped
// cell of degree 2, p2, centred or moved by `offset`, with or without adhesion; transverse, or the
// whole ply (`macro` full: the strain and the shears along the fibres too).
#include <Eigen/Core>

#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "mesh/mesh.hpp"
#include "test_util.hpp"

namespace dualcell::testing {

inline law::CondensedCell periodic_contact_cell(const Eigen::Vector2d& offset, double strength = 0,
                                                Macro macro = Macro::transverse) {
  Scene s = parse_scene(scene_text(1, 1, 2, 0.3), "test.toml");
  s.geometry.element = Element::p2;
  s.geometry.fibre_offset = {offset.x(), offset.y()};
  s.fibre = {30.0, 0.22};
  s.matrix = {1.0, 0.35};
  s.load.boundary = Boundary::periodic;
  s.load.macro = macro;
  s.interface.normal_strength = s.interface.tangential_strength = strength;
  const mesh::Mesh mesh = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(mesh, s);
  return feti::condense(solver.setup());
}

}  // namespace dualcell::testing
