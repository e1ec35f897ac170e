#pragma once
// A structure scene (structure.toml, keys in README.md "Stage: dualcell-structure"): a
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

#include "core/scene.hpp"

namespace dualcell {

enum class EdgeKind { free, fixed, roller, displacement, traction };

// One edge of the rectangle: left (x = 0), right (x = L), bottom (y = 0), top (y = H). Its
// start is the bottom or left corner; a traction varies linearly from start to end.
struct EdgeCondition {
  EdgeKind kind = EdgeKind::free;
  // displacement: the prescribed components (NaN: that component is free)
  Eigen::Vector2d displacement{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  Eigen::Vector2d traction_start = Eigen::Vector2d::Zero(), traction_end = Eigen::Vector2d::Zero();
};
inline constexpr std::array<const char*, 4> edge_names = {"left", "right", "bottom", "top"};

struct Support {  // the node at `at`, held in x and/or y
  Eigen::Vector2d at = Eigen::Vector2d::Zero();
  bool fix_x = false, fix_y = false;
};

struct PointLoad {  // a force at the node at `at`
  Eigen::Vector2d at = Eigen::Vector2d::Zero(), force = Eigen::Vector2d::Zero();
};

struct StructureScene {
  int nx = 1, ny = 1;         // cells along x and y
  double cell_size = 1;       // side of one cell: the fitted cell's (from law.h5), not a key
  int elements_per_cell = 2;  // m: m × m squares per cell, two triangles each
  Element element = Element::p2;
  std::array<EdgeCondition, 4> edges;  // in the order of edge_names
  std::vector<Support> supports;
  std::vector<PointLoad> point_loads;
  std::vector<double> factors = {1.0};              // load steps: loads and prescribed displacements × factor
  Eigen::Vector2d watch = Eigen::Vector2d::Zero();  // the node whose displacement is reported per step
  double tolerance = 1e-10;                         // Newton: ‖r‖ ≤ tolerance · max(‖f_int‖, ‖f‖)
  int max_newton_steps = 100;
  int max_fuse_rounds = 1000;
  std::string text;  // the file as read, for provenance
};

StructureScene parse_structure_scene(std::string_view text, const std::filesystem::path& file);
StructureScene load_structure_scene(const std::filesystem::path& file);

}  // namespace dualcell
