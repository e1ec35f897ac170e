#include "rve/microstructure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/error.hpp"
#include "core/text.hpp"
#include "rve/disk_grid.hpp"

namespace dualcell::rve {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// How a fibre meets the two edge lines of one direction (x or y) at 0 and L: its centre's
// distance d to the nearer one. Clear when d ≥ r + gap, crossing when d ≤ r − gap (the chord
// the edge cuts is no sliver), too close otherwise.
enum class Edge { clear, crossing, too_close };
Edge edge_state(double c, double r, double L, double gap) {
  const double d = std::min(c, L - c);
  if (d >= r + gap) return Edge::clear;
  if (d <= r - gap) return Edge::crossing;
  return Edge::too_close;
}

// Whether fibre f may stand where it is against the edges: not too close to one, not across a
// corner (an x and a y edge at once).
bool edges_allow(const Microstructure& m, const Fibre& f, double gap) {
  const Edge x = edge_state(f.centre.x(), f.radius, m.Lx, gap), y = edge_state(f.centre.y(), f.radius, m.Ly, gap);
  return x != Edge::too_close && y != Edge::too_close && !(x == Edge::crossing && y == Edge::crossing);
}

double surface_gap(const Microstructure& m, const Fibre& a, const Fibre& b) {
  return periodic_offset(m, a.centre, b.centre).norm() - a.radius - b.radius;
}

double largest_radius(const Microstructure& m) {
  double r = 0;
  for (const Fibre& f : m.fibres) r = std::max(r, f.radius);
  return r;
}

// The fibres of m binned by their centres, periodically: every fibre within `reach` (centre to
// centre, nearest image) of a place is among those near() visits.
DiskGrid grid_of(const Microstructure& m, double reach) {
  DiskGrid grid(0, 0, m.Lx, m.Ly, reach, true);
  for (std::size_t j = 0; j < m.fibres.size(); ++j) grid.insert(static_cast<int>(j), m.fibres[j].centre);
  return grid;
}

// Whether fibre `f` keeps `gap` to the fibres of `grid` (of m) except `skip`: a fibre nearer than
// that has its centre within r + r_max + gap, which the grid's reach covers.
bool fits(const Microstructure& m, const DiskGrid& grid, const Fibre& f, std::size_t skip, double gap) {
  if (!edges_allow(m, f, gap)) return false;
  bool ok = true;
  grid.near(f.centre, [&](int j) {
    if (ok && static_cast<std::size_t>(j) != skip && surface_gap(m, f, m.fibres[j]) < gap) ok = false;
  });
  return ok;
}

Eigen::Vector2d wrapped(const Microstructure& m, Eigen::Vector2d c) {
  c.x() -= m.Lx * std::floor(c.x() / m.Lx);
  c.y() -= m.Ly * std::floor(c.y() / m.Ly);
  // floor can leave c == L by round-off: the rectangle is [0, L).
  if (c.x() >= m.Lx) c.x() = 0;
  if (c.y() >= m.Ly) c.y() = 0;
  return c;
}

std::string fibre_text(const Fibre& f, std::size_t i) {
  return "fibre " + std::to_string(i + 1) + " at (" + shortest(f.centre.x()) + ", " + shortest(f.centre.y()) +
         "), radius " + shortest(f.radius);
}

void check_spec(double Lx, double Ly, const RandomFibres& s, const std::string& where) {
  const auto bad = [&](const std::string& key, double value, const std::string& range) {
    throw InputError(where + ": " + key + " = " + shortest(value) + ": out of range: " + range);
  };
  if (!(Lx > 0 && Ly > 0 && std::isfinite(Lx) && std::isfinite(Ly))) bad("size", std::min(Lx, Ly), "each > 0");
  if (!(s.volume_fraction > 0 && s.volume_fraction < 0.9)) bad("volume_fraction", s.volume_fraction, "(0, 0.9)");
  if (!(s.radius_mean > 0 && std::isfinite(s.radius_mean))) bad("radius", s.radius_mean, "mean > 0");
  if (!(s.radius_sd >= 0 && s.radius_sd <= 0.25 * s.radius_mean))
    bad("radius standard deviation", s.radius_sd, "[0, mean/4]");
  if (!(s.min_gap >= 0 && s.min_gap < s.radius_mean)) bad("min_gap", s.min_gap, "[0, mean radius)");
  const double largest = s.radius_mean + 2 * s.radius_sd;
  if (!(2 * (largest + s.min_gap) < std::min(Lx, Ly)))
    bad("radius", s.radius_mean, "the largest fibre with its gap must fit the rectangle twice over");
  if (s.max_shake_sweeps < 0) bad("max_shake_sweeps", s.max_shake_sweeps, ">= 0");
}

// Radii to the volume fraction: drawn until their area passes it (the count nearer to it
// kept), then scaled by one common factor so that Σπr² = v_f Lx Ly exactly.
std::vector<double> draw_radii(double Lx, double Ly, const RandomFibres& s, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(s.radius_mean, s.radius_sd);
  const double target = s.volume_fraction * Lx * Ly;
  // Fewer than half a fibre of the mean radius: the one fibre would be scaled down to a radius
  // far from the asked one (and its mesh to elements far smaller than the rectangle needs).
  const double one = std::numbers::pi * s.radius_mean * s.radius_mean;
  if (target < 0.5 * one)
    throw InputError("volume_fraction = " + shortest(s.volume_fraction) + " is less than half of one fibre of radius " +
                     shortest(s.radius_mean) + " in " + shortest(Lx) + " x " + shortest(Ly) + " (which alone is " +
                     formatted("%.3g", one / (Lx * Ly)) + "): raise it or the size, or lower the radius");
  std::vector<double> radii;
  double area = 0;
  while (area < target) {
    double r = s.radius_mean;
    if (s.radius_sd > 0) do
        r = normal(rng);
      while (std::abs(r - s.radius_mean) > 2 * s.radius_sd);
    const double a = std::numbers::pi * r * r;
    if (area + a > target && (area + a - target) > (target - area) && !radii.empty()) break;
    radii.push_back(r);
    area += a;
  }
  const double scale = std::sqrt(target / area);
  for (double& r : radii) r *= scale;
  std::sort(radii.begin(), radii.end(), std::greater<>());  // the largest first: they jam first
  return radii;
}

}  // namespace

double Microstructure::volume_fraction() const {
  double area = 0;
  for (const Fibre& f : fibres) area += std::numbers::pi * f.radius * f.radius;
  return area / (Lx * Ly);
}

Eigen::Vector2d periodic_offset(const Microstructure& m, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  Eigen::Vector2d d = b - a;
  d.x() -= m.Lx * std::round(d.x() / m.Lx);
  d.y() -= m.Ly * std::round(d.y() / m.Ly);
  return d;
}

Statistics statistics(const Microstructure& m) {
  Statistics s;
  s.fibres = static_cast<int>(m.fibres.size());
  s.volume_fraction = m.volume_fraction();
  s.neighbour_min = s.gap_min = s.edge_gap_min = inf;
  double sum = 0, sum2 = 0;
  // Neighbours from a grid whose reach is a few mean spacings (and at least two radii): a fibre
  // whose nearest neighbour lies beyond it (a sparse microstructure) is compared with all.
  const double spacing = std::sqrt(m.Lx * m.Ly / std::max<std::size_t>(1, m.fibres.size()));
  const double reach = std::max(3 * spacing, 2 * largest_radius(m));
  const DiskGrid grid = grid_of(m, reach);
  for (std::size_t i = 0; i < m.fibres.size(); ++i) {
    const Fibre& f = m.fibres[i];
    double nearest = inf;
    const auto neighbour = [&](std::size_t j) {
      if (j == i) return;
      nearest = std::min(nearest, periodic_offset(m, f.centre, m.fibres[j].centre).norm());
      s.gap_min = std::min(s.gap_min, surface_gap(m, f, m.fibres[j]));
    };
    grid.near(f.centre, [&](int j) { neighbour(static_cast<std::size_t>(j)); });
    // Every pair nearer than `reach` was seen; beyond it, all of them.
    if (!(nearest < reach))
      for (std::size_t j = 0; j < m.fibres.size(); ++j) neighbour(j);
    if (std::isfinite(nearest)) {
      sum += nearest;
      sum2 += nearest * nearest;
      s.neighbour_min = std::min(s.neighbour_min, nearest);
    }
    bool crossing = false;
    for (const auto& [c, L] : {std::pair{f.centre.x(), m.Lx}, std::pair{f.centre.y(), m.Ly}}) {
      // The rim's distance to the edge line: a gap, or for a fibre the line cuts the width of
      // the sliver beyond it (what the mesh must resolve either way).
      const double d = std::min(c, L - c);
      crossing = crossing || d < f.radius;
      s.edge_gap_min = std::min(s.edge_gap_min, std::abs(d - f.radius));
    }
    s.crossing_edges += crossing ? 1 : 0;
  }
  // A pair with a centre distance beyond `reach` has a gap above reach − 2 r_max; when no pair
  // seen has a smaller one, the smallest gap may be such a pair's: all pairs then.
  if (std::isfinite(s.gap_min) && s.gap_min > reach - 2 * largest_radius(m))
    for (std::size_t i = 0; i < m.fibres.size(); ++i)
      for (std::size_t j = 0; j < i; ++j) s.gap_min = std::min(s.gap_min, surface_gap(m, m.fibres[i], m.fibres[j]));
  if (s.fibres > 1) {
    s.neighbour_mean = sum / s.fibres;
    s.neighbour_sd = std::sqrt(std::max(0.0, sum2 / s.fibres - s.neighbour_mean * s.neighbour_mean));
  }
  return s;
}

void check(const Microstructure& m, double min_gap, const std::string& where) {
  // Radii first (the grid's reach needs them), then each fibre against the edges and the
  // fibres before it.
  for (std::size_t i = 0; i < m.fibres.size(); ++i)
    if (!(m.fibres[i].radius > 0) || !std::isfinite(m.fibres[i].radius))
      throw InputError(where + ": " + fibre_text(m.fibres[i], i) + ": the radius must be > 0");
  const DiskGrid grid = grid_of(m, 2 * largest_radius(m) + min_gap);
  for (std::size_t i = 0; i < m.fibres.size(); ++i) {
    const Fibre& f = m.fibres[i];
    const std::string what = where + ": " + fibre_text(f, i);
    if (!(f.radius > 0) || !std::isfinite(f.radius)) throw InputError(what + ": the radius must be > 0");
    if (!(f.centre.x() >= 0 && f.centre.x() < m.Lx && f.centre.y() >= 0 && f.centre.y() < m.Ly))
      throw InputError(what + ": the centre must lie in [0, " + shortest(m.Lx) + ") × [0, " + shortest(m.Ly) + ")");
    if (!(2 * (f.radius + min_gap) < std::min(m.Lx, m.Ly)))
      throw InputError(what + ": larger than half the rectangle, it would meet its own periodic image");
    const Edge x = edge_state(f.centre.x(), f.radius, m.Lx, min_gap),
               y = edge_state(f.centre.y(), f.radius, m.Ly, min_gap);
    if (x == Edge::crossing && y == Edge::crossing)
      throw InputError(what + ": crosses two edges at a corner, which the periodic mesh cannot resolve");
    if (x == Edge::too_close || y == Edge::too_close)
      throw InputError(what + ": closer than min_gap = " + shortest(min_gap) +
                       " to an edge, or cut by it in a sliver thinner than that");
    // The first earlier fibre nearer than min_gap: its centre lies within 2 r_max + min_gap.
    std::size_t first = i;
    grid.near(f.centre, [&](int j) {
      const auto k = static_cast<std::size_t>(j);
      if (k < first && surface_gap(m, m.fibres[k], f) < min_gap) first = k;
    });
    if (first < i) {
      const double gap = surface_gap(m, m.fibres[first], f);
      throw InputError(what + ": " +
                       (gap < 0 ? "overlaps " : "is closer than min_gap = " + shortest(min_gap) + " to ") +
                       fibre_text(m.fibres[first], first) + " (gap " + formatted("%.3g", gap) + ")");
    }
  }
}

Microstructure generate_random(double Lx, double Ly, const RandomFibres& spec, const std::string& where) {
  check_spec(Lx, Ly, spec, where);
  std::mt19937_64 rng(spec.seed);
  Microstructure m;
  m.Lx = Lx;
  m.Ly = Ly;
  std::vector<double> radii;
  try {
    radii = draw_radii(Lx, Ly, spec, rng);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto random_centre = [&] { return Eigen::Vector2d(Lx * unit(rng), Ly * unit(rng)); };
  constexpr int attempts_per_fibre = 2000;
  const double gap = spec.min_gap;
  // The placed fibres binned (radii sorted largest first: radii[0] is the largest).
  DiskGrid grid(0, 0, Lx, Ly, 2 * radii.front() + gap, true);
  // Insertion of fibre k by RSA: `attempts` random centres, the first that fits is kept.
  const auto insert = [&](std::size_t k, int attempts) {
    Fibre f{Eigen::Vector2d::Zero(), radii[k]};
    for (int a = 0; a < attempts; ++a) {
      f.centre = random_centre();
      if (fits(m, grid, f, m.fibres.size(), gap)) {
        m.fibres.push_back(f);
        grid.insert(static_cast<int>(m.fibres.size()) - 1, f.centre);
        return true;
      }
    }
    return false;
  };
  // A shaking sweep: every placed fibre one random move of at most `step`, kept when it fits.
  // The step adapts to keep about a third of the moves (small steps at high density).
  double step = spec.radius_mean;
  const auto shake = [&] {
    int accepted = 0;
    for (std::size_t i = 0; i < m.fibres.size(); ++i) {
      Fibre moved = m.fibres[i];
      moved.centre = wrapped(m, moved.centre + step * Eigen::Vector2d(2 * unit(rng) - 1, 2 * unit(rng) - 1));
      if (fits(m, grid, moved, i, gap)) {
        grid.remove(static_cast<int>(i), m.fibres[i].centre);
        grid.insert(static_cast<int>(i), moved.centre);
        m.fibres[i] = moved;
        ++accepted;
      }
    }
    const double rate = static_cast<double>(accepted) / static_cast<double>(std::max<std::size_t>(1, m.fibres.size()));
    step *= rate > 0.4 ? 1.2 : rate < 0.25 ? 0.8 : 1.0;
    step = std::clamp(step, 1e-4 * spec.radius_mean, spec.radius_mean);
  };
  int sweeps = 0;
  for (std::size_t k = 0; k < radii.size(); ++k) {
    if (insert(k, attempts_per_fibre)) continue;
    // Jammed: shake, then try again with fewer attempts, until the fibre goes in or the sweeps
    // run out.
    bool placed = false;
    while (!placed && sweeps < spec.max_shake_sweeps) {
      shake();
      ++sweeps;
      placed = insert(k, 50);
    }
    if (!placed)
      throw InputError(where + ": the fibres jam at volume fraction " + formatted("%.4f", m.volume_fraction()) + " (" +
                       std::to_string(m.fibres.size()) + " of " + std::to_string(radii.size()) + " placed) short of " +
                       shortest(spec.volume_fraction) + " after " + std::to_string(sweeps) +
                       " shaking sweeps: lower volume_fraction or min_gap");
  }
  // A few sweeps more, so that the last fibres are not where RSA left them in the last holes.
  for (int s = 0; s < std::min(50, spec.max_shake_sweeps); ++s) shake();
  return m;
}

Microstructure microstructure_of(const Geometry& geometry, const std::string& where) {
  if (geometry.layout == FibreLayout::random)
    return generate_random(geometry.size[0], geometry.size[1], geometry.random, where + ": [geometry]");
  Microstructure m;
  m.Lx = geometry.size[0];
  m.Ly = geometry.size[1];
  for (const FibreCircle& f : geometry.fibres) m.fibres.push_back({{f.centre[0], f.centre[1]}, f.radius});
  check(m, geometry.random.min_gap, where + ": [[fibres]]");
  return m;
}

}  // namespace dualcell::rve
