#include "core/edge_loads.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "core/text.hpp"

namespace dualcell {

std::string position_text(const std::string& where, const char* what, const Eigen::Vector2d& at) {
  return (where.empty() ? std::string(what) : where) + " at (" + shortest(at.x()) + ", " + shortest(at.y()) + ")";
}

std::string free_rigid_motion(const EdgeLoads& loads, double width, double height,
                              const std::function<bool(const Eigen::Vector2d&)>& holds) {
  // Rows (in units of the larger side, so that the rank test is scale-free): a held x component
  // at (x, y) sees a − ω y, a held y component b + ω x.
  const double L = std::max(width, height);
  std::vector<Eigen::RowVector3d> rows;
  const auto hold = [&](const Eigen::Vector2d& at, int component) {
    const Eigen::Vector2d p = at / L;
    rows.push_back(component == 0 ? Eigen::RowVector3d(1, 0, -p.y()) : Eigen::RowVector3d(0, 1, p.x()));
  };
  const std::array<std::array<Eigen::Vector2d, 2>, 4> ends = {{{{{0, 0}, {0, height}}},
                                                               {{{width, 0}, {width, height}}},
                                                               {{{0, 0}, {width, 0}}},
                                                               {{{0, height}, {width, height}}}}};
  for (int e = 0; e < 4; ++e) {
    const EdgeCondition& c = loads.edges[e];
    const int normal = e < 2 ? 0 : 1;
    for (const Eigen::Vector2d& at : ends[e]) {
      if (c.kind == EdgeKind::fixed) hold(at, 0), hold(at, 1);
      if (c.kind == EdgeKind::roller) hold(at, normal);
      if (c.kind == EdgeKind::displacement)
        for (int k = 0; k < 2; ++k)
          if (!std::isnan(c.displacement(k))) hold(at, k);
    }
  }
  for (const Support& s : loads.supports) {
    if (holds && !holds(s.at)) continue;
    if (s.fix_x) hold(s.at, 0);
    if (s.fix_y) hold(s.at, 1);
  }
  Eigen::MatrixXd M(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i) M.row(static_cast<Eigen::Index>(i)) = rows[i];
  const bool x_held = rows.empty() ? false : M.col(0).cwiseAbs().maxCoeff() > 0;
  const bool y_held = rows.empty() ? false : M.col(1).cwiseAbs().maxCoeff() > 0;
  const std::string x_hint =
      "hold x somewhere (a [[support]] with fix = \"x\" or \"xy\", a fixed edge, a roller on the left or right edge, "
      "or a displacement edge with ux)";
  const std::string y_hint =
      "hold y somewhere (a [[support]] with fix = \"y\" or \"xy\", a fixed edge, a roller on the bottom or top edge, "
      "or a displacement edge with uy)";
  if (!x_held && !y_held) return "every translation and the rotation: " + x_hint + " and " + y_hint;
  if (!x_held) return "the translation along x: " + x_hint;
  if (!y_held) return "the translation along y: " + y_hint;
  // Both translations are seen; the rank is 3 unless some rotation about a point is free.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeFullV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  if (sigma.size() == 3 && sigma(2) > 1e-9 * sigma(0)) return "";
  const Eigen::Vector3d v = svd.matrixV().col(2);                        // (a, b, ω): the free motion
  if (std::abs(v(2)) < 1e-12) return "";                                 // cannot happen with both translations seen
  const double cx = -v(1) / v(2) * L + 0.0, cy = v(0) / v(2) * L + 0.0;  // + 0.0: no "-0" in messages
  return "a rotation about (" + shortest(cx) + ", " + shortest(cy) +
         "): hold a second point away from it (another [[support]], or a fixed, roller or displacement edge)";
}

}  // namespace dualcell
