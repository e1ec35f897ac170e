#pragma once
// A structure scene (structure.toml, keys in docs/reference/scene-keys.md): a
// rectangle of nx × ny homogeneous cells, its edge conditions, supports, point loads and load
// steps. Read by parse_structure_scene, which checks the TOML, every key's type and range, and
// names the file, line, key and value of anything wrong.
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "core/edge_loads.hpp"
#include "core/scene.hpp"

namespace dualcell {

// The edge conditions, supports, point loads, steps and watch point are those of EdgeLoads.
struct StructureScene : EdgeLoads {
  int nx = 1, ny = 1;         // cells along x and y
  double cell_size = 1;       // side of one cell: the fitted cell's (from law.h5), not a key
  int elements_per_cell = 2;  // m: m × m squares per cell, two triangles each
  Element element = Element::p2;
  // Quadrature points per p2 triangle: 6 (degree 4, the default) or 3 (degree 2, as CalculiX's
  // CPE6 and C3D15 integrate: a structure compared with them point by point, past the fuse).
  int quadrature = 6;
  // The exact law's bond history (law/condensed.hpp): per cell (every point of a cell shares its
  // bonds; the cell's debond cascade runs at its mean strain) or per quadrature point.
  enum class BondUnit { cell, point } bond_unit = BondUnit::cell;
  double tolerance = 1e-10;  // Newton: ‖r‖ ≤ tolerance · max(‖f_int‖, ‖f‖)
  int max_newton_steps = 100;
  int max_fuse_rounds = 1000;
  std::string text;  // the file as read, for provenance
};

StructureScene parse_structure_scene(std::string_view text, const std::filesystem::path& file);
StructureScene load_structure_scene(const std::filesystem::path& file);

}  // namespace dualcell
