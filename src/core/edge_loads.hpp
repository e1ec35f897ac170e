#pragma once
// Edge conditions of a rectangle, shared by the structure of homogeneous cells
// (structure.toml) and the resolved block of cells with `[load] boundary = "edges"`
// (scene.toml): per edge fixed, roller, prescribed displacement or a traction varying linearly
// along it; point supports and point loads at nodes; proportional load steps and the node whose
// displacement is reported. Keys in docs/reference/scene-keys.md.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <limits>
#include <string>
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

  // The traction at the fraction `along` (0 at the start, 1 at the end) of the edge: linear from start to end.
  Eigen::Vector2d traction_at(double along) const { return traction_start + along * (traction_end - traction_start); }
};
inline constexpr std::array<const char*, 4> edge_names = {"left", "right", "bottom", "top"};

// The one tolerance rule for "the node at a position" (a support, a point load, a watch point,
// fem::node_near) and for the meshers' "on a side, at the same place" (mesh::side_tolerance): within
// 1e-9 of the size of the body (its larger side).
inline double node_reach(double body_size) { return 1e-9 * body_size; }

// `where` is the place it was written ("beam.toml:12: [[support]] 1"), for messages that find
// no node there; empty for loads built in code.
struct Support {  // the node at `at`, held in x and/or y
  Eigen::Vector2d at = Eigen::Vector2d::Zero();
  bool fix_x = false, fix_y = false;
  std::string where;
};

struct PointLoad {  // a force at the node at `at`
  Eigen::Vector2d at = Eigen::Vector2d::Zero(), force = Eigen::Vector2d::Zero();
  std::string where;
};

struct EdgeLoads {
  std::array<EdgeCondition, 4> edges;  // in the order of edge_names
  std::vector<Support> supports;
  std::vector<PointLoad> point_loads;
  std::vector<double> factors = {1.0};              // load steps: loads and prescribed displacements × factor
  Eigen::Vector2d watch = Eigen::Vector2d::Zero();  // the node whose displacement is reported per step
  std::string watch_where;                          // where [output] watch was written, if it was
};

// A position for messages: "beam.toml:12: [[support]] 1 at (0, 0.5)" when it was written in a
// scene (`where`), "support at (0, 0.5)" when it was built in code.
std::string position_text(const std::string& where, const char* what, const Eigen::Vector2d& at);

// The rigid-body motions of the rectangle [0, width] × [0, height] that its edge conditions and
// supports leave free: empty when every translation and rotation is held, else one phrase naming
// the motion left free and what would hold it ("a rotation about (0, 0): hold a second point
// ..."). A rigid motion u(x) = (a − ω y, b + ω x) is held when some held component sees it; the
// held components (edge end points, supports) form the rows of a 3-column matrix whose rank is
// 3 exactly when nothing is free. `holds` says whether a support at a point holds the body in
// question (a support inside a fibre of a resolved block holds that fibre only).
std::string free_rigid_motion(const EdgeLoads& loads, double width, double height,
                              const std::function<bool(const Eigen::Vector2d&)>& holds = {});

}  // namespace dualcell
