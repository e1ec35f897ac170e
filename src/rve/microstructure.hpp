#pragma once
// The fibres of a periodic representative volume (docs/method.md §16b): a rectangle Lx × Ly whose
// fibres are circles, given as a list (a microstructure measured from a micrograph) or generated
// at random to a volume fraction. Periodic: a fibre crossing an edge continues across the
// opposite one, so distances are taken to the nearest periodic image and the volume fraction
// is Σ πr² / (Lx Ly) however the fibres lie.
//
// Generation (generate_random): radii drawn from a normal distribution (mean, standard
// deviation, truncated to ±2 standard deviations), placed by random sequential adsorption
// (RSA, a uniformly random centre, kept when it keeps min_gap to every fibre placed and to
// the edges it does not cross). RSA jams near v_f 0.55; past that, the placed fibres are shaken
// (a hard-disk Monte Carlo move per fibre: a random displacement kept when it keeps every gap),
// which opens room for the next ones, densification by perturbation (docs/method.md §16b).
// Reproducible: one std::mt19937_64 seeded with `seed`, consumed in a fixed order.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/scene.hpp"

namespace dualcell::rve {

struct Fibre {
  Eigen::Vector2d centre;
  double radius = 0;
};

struct Microstructure {
  double Lx = 1, Ly = 1;
  std::vector<Fibre> fibres;
  double volume_fraction() const;
};

// Nearest-neighbour statistics of a microstructure (periodic distances between centres, and the
// gaps between surfaces), and the smallest gap to an edge of a fibre that does not cross it.
struct Statistics {
  int fibres = 0;
  double volume_fraction = 0;
  double neighbour_mean = 0, neighbour_sd = 0, neighbour_min = 0;  // centre to nearest centre
  double gap_min = 0;                                              // surface to nearest surface
  // The smallest distance between a rim and an edge line: a fibre's gap to an edge, or the
  // width of the sliver of a fibre that an edge cuts; +inf without fibres.
  double edge_gap_min = 0;
  int crossing_edges = 0;  // fibres cut by an edge (they continue across the opposite one)
};
Statistics statistics(const Microstructure& m);

// The periodic distance vector from a to b (the nearest image of b).
Eigen::Vector2d periodic_offset(const Microstructure& m, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

// An InputError naming `where` and the first problem: a radius ≤ 0 or a centre outside the
// rectangle, two fibres closer than min_gap (overlap included), a fibre crossing two edges at a
// corner (the periodic mesher cannot resolve it), a fibre closer than min_gap to an edge it does
// not cross, or a fibre larger than the rectangle.
void check(const Microstructure& m, double min_gap, const std::string& where);

// Random fibres to spec.volume_fraction in Lx × Ly (see the file comment). An InputError when the
// spec is out of range, or, naming the volume fraction reached, when the fibres jam.
Microstructure generate_random(double Lx, double Ly, const RandomFibres& spec, const std::string& where);

// The fibres of an RVE geometry: the list, checked (rve::check), or random fibres generated
// (rve::generate_random). `where` names the scene in messages.
Microstructure microstructure_of(const Geometry& geometry, const std::string& where);

}  // namespace dualcell::rve
