#pragma once
// Edge conditions of a rectangle, shared by the structure of homogeneous cells
// (structure.toml) and the resolved block of cells with `[load] boundary = "edges"`
// (scene.toml): per edge fixed, roller, prescribed displacement or a traction varying linearly
// along it; point supports and point loads at nodes; proportional load steps and the node whose
// displacement is reported. Keys in README.md ("Stage: dualcell-structure").
#include <Eigen/Core>
#include <array>
#include <limits>
#include <vector>

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

struct EdgeLoads {
  std::array<EdgeCondition, 4> edges;  // in the order of edge_names
  std::vector<Support> supports;
  std::vector<PointLoad> point_loads;
  std::vector<double> factors = {1.0};              // load steps: loads and prescribed displacements × factor
  Eigen::Vector2d watch = Eigen::Vector2d::Zero();  // the node whose displacement is reported per step
};

}  // namespace dualcell
