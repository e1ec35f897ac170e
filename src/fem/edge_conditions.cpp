#include "fem/edge_conditions.hpp"

#include <cmath>
#include <set>
#include <utility>

#include "fem/element.hpp"

namespace dualcell::fem {

std::vector<HeldComponent> held_components(const EdgeLoads& loads, const std::array<std::vector<int>, 4>& edge_points,
                                           const std::function<int(const Support&)>& support_point) {
  std::vector<HeldComponent> held;
  std::set<std::pair<int, int>> seen;
  const auto hold = [&](int point, int component, double value, int by) {
    if (seen.insert({point, component}).second) held.push_back({point, component, value, by});
  };
  for (int e = 0; e < 4; ++e) {
    const EdgeCondition& c = loads.edges[e];
    const int normal = e < 2 ? 0 : 1;
    for (int point : edge_points[e]) {
      if (c.kind == EdgeKind::fixed) hold(point, 0, 0, e), hold(point, 1, 0, e);
      if (c.kind == EdgeKind::roller) hold(point, normal, 0, e);
      if (c.kind == EdgeKind::displacement)
        for (int k = 0; k < 2; ++k)
          if (!std::isnan(c.displacement(k))) hold(point, k, c.displacement(k), e);
    }
  }
  for (const Support& s : loads.supports) {
    const int point = support_point(s);
    if (s.fix_x) hold(point, 0, 0, held_by_support);
    if (s.fix_y) hold(point, 1, 0, held_by_support);
  }
  return held;
}

void add_edge_traction(std::span<const Eigen::Vector2d> x, std::span<const int> nodes, const Eigen::Vector2d& t_a,
                       const Eigen::Vector2d& t_b, Eigen::VectorXd& f) {
  // ∫ φ_i t ds with t linear in the edge parameter s and ds = |x'(s)| ds.
  const int n = static_cast<int>(x.size());
  for (const EdgePoint& q : edge_rule()) {
    double phi[3], dphi[3];
    edge_shape(n, q.s, phi, dphi);
    Eigen::Vector2d dx = Eigen::Vector2d::Zero();
    for (int i = 0; i < n; ++i) dx += dphi[i] * x[i];
    const Eigen::Vector2d t = (1 - q.s) * t_a + q.s * t_b;
    for (int i = 0; i < n; ++i) f.segment<2>(2 * nodes[i]) += (q.weight * dx.norm() * phi[i]) * t;
  }
}

}  // namespace dualcell::fem
