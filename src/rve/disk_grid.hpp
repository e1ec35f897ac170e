#pragma once
// Points (the centres of fibres) binned on a grid, so that those near a place are found without
// looking at all of them (cell lists): the placement of random fibres, their checks and
// statistics, and the mesh size field cost O(N) for N fibres instead of O(N²).
//
// The bins are at least `reach` on a side, so every point within `reach` of a place lies in the
// 3 × 3 bins around it. Periodic: the box wraps, and a query near an edge sees the bins across
// it (its caller measures distances to the nearest periodic image).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

namespace dualcell::rve {

class DiskGrid {
 public:
  DiskGrid(double x0, double y0, double width, double height, double reach, bool periodic)
      : x0_(x0), y0_(y0), periodic_(periodic) {
    // Bins of at least `reach`, at most max_bins a side (a larger bin is still correct).
    const auto count = [&](double length) {
      const double n = reach > 0 ? std::floor(length / reach) : 1.0;
      return static_cast<int>(std::clamp(n, 1.0, static_cast<double>(max_bins)));
    };
    nx_ = count(width), ny_ = count(height);
    bx_ = width / nx_, by_ = height / ny_;
    bins_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  }
  void insert(int item, const Eigen::Vector2d& p) { bins_[bin(p)].push_back(item); }
  void remove(int item, const Eigen::Vector2d& p) {
    auto& b = bins_[bin(p)];
    b.erase(std::find(b.begin(), b.end(), item));
  }
  // visit(item) for every item in the bins within one bin of p's: every item within `reach` of
  // p (periodically when the grid is), and maybe some more; each once.
  template <class Visit>
  void near(const Eigen::Vector2d& p, Visit&& visit) const {
    const int ix = index((p.x() - x0_) / bx_, nx_), iy = index((p.y() - y0_) / by_, ny_);
    // Periodic with fewer than 3 bins a side: every bin of that side, once.
    const int x_from = periodic_ && nx_ < 3 ? 0 : ix - 1, x_to = periodic_ && nx_ < 3 ? nx_ - 1 : ix + 1;
    const int y_from = periodic_ && ny_ < 3 ? 0 : iy - 1, y_to = periodic_ && ny_ < 3 ? ny_ - 1 : iy + 1;
    for (int jy = y_from; jy <= y_to; ++jy)
      for (int jx = x_from; jx <= x_to; ++jx) {
        int kx = jx, ky = jy;
        if (periodic_) {
          kx = (jx % nx_ + nx_) % nx_, ky = (jy % ny_ + ny_) % ny_;
        } else if (jx < 0 || jx >= nx_ || jy < 0 || jy >= ny_) {
          continue;
        }
        for (const int item : bins_[static_cast<std::size_t>(ky) * nx_ + kx]) visit(item);
      }
  }

 private:
  static constexpr int max_bins = 2048;
  int index(double t, int n) const {
    const double i = std::floor(t);
    if (periodic_) return static_cast<int>(((static_cast<long>(std::clamp(i, -1e9, 1e9)) % n) + n) % n);
    return static_cast<int>(std::clamp(i, 0.0, static_cast<double>(n - 1)));
  }
  std::size_t bin(const Eigen::Vector2d& p) const {
    return static_cast<std::size_t>(index((p.y() - y0_) / by_, ny_)) * nx_ + index((p.x() - x0_) / bx_, nx_);
  }
  double x0_, y0_, bx_ = 1, by_ = 1;
  int nx_ = 1, ny_ = 1;
  bool periodic_;
  std::vector<std::vector<int>> bins_;
};

}  // namespace dualcell::rve
