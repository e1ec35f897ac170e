#include "core/scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"

namespace dualcell {

const char* to_string(Preconditioner p) {
  switch (p) {
    case Preconditioner::none:
      return "none";
    case Preconditioner::lumped:
      return "lumped";
    case Preconditioner::dirichlet:
      return "dirichlet";
  }
  return "?";
}

const char* to_string(DualOperator o) {
  switch (o) {
    case DualOperator::automatic:
      return "auto";
    case DualOperator::implicit:
      return "implicit";
    case DualOperator::explicit_:
      return "explicit";
  }
  return "?";
}

const char* to_string(Element e) { return e == Element::p1 ? "p1" : "p2"; }

const char* to_string(FibreLayout l) {
  switch (l) {
    case FibreLayout::cells:
      return "cells";
    case FibreLayout::list:
      return "list";
    case FibreLayout::random:
      return "random";
  }
  return "?";
}

const char* to_string(Boundary b) {
  switch (b) {
    case Boundary::symmetry:
      return "symmetry";
    case Boundary::traction:
      return "traction";
    case Boundary::periodic:
      return "periodic";
    case Boundary::edges:
      return "edges";
  }
  return "?";
}

namespace {

// Refuses a value with the key's place and text as written when the scene came from a file,
// else with the file name (or "scene") and the value as stored.
class Checker {
 public:
  explicit Checker(const Scene& scene) : scene_(scene) {}

  [[noreturn]] void fail(const char* table, const char* key, const std::string& value, const std::string& why) const {
    const auto at = scene_.written.find(std::string(table) + "." + key);
    const bool known = at != scene_.written.end();
    const std::string where = known ? at->second.where : scene_.file.empty() ? "scene" : scene_.file.string();
    const std::string shown = known ? at->second.value : value;
    throw InputError(where + ": [" + table + "] " + key + (shown.empty() ? "" : " = " + clipped(shown)) + ": " + why);
  }

  template <typename Ok>
  void real(const char* table, const char* key, double v, Ok ok, const std::string& range) const {
    if (!(std::isfinite(v) && ok(v))) fail(table, key, shortest(v), "out of range: " + range);
  }

  void integer(const char* table, const char* key, long v, long lo, long hi) const {
    if (v < lo || v > hi)
      fail(table, key, std::to_string(v),
           "out of range: an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }

  template <typename Ok>
  void reals(const char* table, const char* key, const std::vector<double>& v, Ok ok, const std::string& what) const {
    for (double x : v)
      if (!(std::isfinite(x) && ok(x))) fail(table, key, shortest(v), "out of range: must be " + what);
  }

 private:
  const Scene& scene_;
};

}  // namespace

namespace {

bool positive(double v) { return v > 0; }
// A cell's lengths: its area (the law's volume) then lies within 1e±100 (law::CondensedCell).
bool length_in_range(double v) { return v >= 1e-50 && v <= 1e50; }
bool non_negative(double v) { return v >= 0; }
bool finite(double) { return true; }

// A periodic RVE's size, fibres and mesh budget (the fibres' positions are checked where they
// are placed, rve/microstructure.hpp).
void validate_rve(const Checker& c, const Scene& scene) {
  const Geometry& geo = scene.geometry;
  c.reals("geometry", "size", {geo.size[0], geo.size[1]}, length_in_range,
          "an array of 2 numbers, each in [1e-50, 1e50] (the cell's area, its law's volume, within 1e±100)");
  c.integer("geometry", "degree", geo.degree, 1, 64);
  c.real("geometry", "min_gap", geo.random.min_gap, non_negative, "min_gap >= 0");
  double r_mean = 0;
  if (geo.layout == FibreLayout::random) {
    const RandomFibres& f = geo.random;
    c.real(
        "geometry", "volume_fraction", f.volume_fraction, [](double v) { return v > 0 && v < 0.9; },
        "0 < volume_fraction < 0.9");
    c.reals("geometry", "radius", {f.radius_mean}, positive, "[mean, sd] with mean > 0");
    c.reals("geometry", "radius", {f.radius_sd}, non_negative, "[mean, sd] with 0 <= sd <= mean/4");
    if (!(f.radius_sd <= 0.25 * f.radius_mean))
      c.fail("geometry", "radius", "",
             "out of range: [mean, sd] with 0 <= sd <= mean/4 (radii are drawn within 2 sd, so the smallest is at "
             "least half the mean, which sets the element size)");
    r_mean = f.radius_mean;
  } else {
    if (geo.fibres.empty()) c.fail("geometry", "size", "", "an RVE of kind \"list\" needs at least one [[fibres]]");
    for (std::size_t k = 0; k < geo.fibres.size(); ++k) {
      const FibreCircle& f = geo.fibres[k];
      if (!(f.radius > 0 && std::isfinite(f.radius)) || !std::isfinite(f.centre[0]) || !std::isfinite(f.centre[1]))
        c.fail("geometry", "size", "",
               "[[fibres]] " + std::to_string(k + 1) + ": the radius must be > 0 and the centre finite");
      r_mean += f.radius / geo.fibres.size();
    }
  }
  // The fibres: listed, or about v_f Lx Ly / (π r²) drawn.
  const double fibres = geo.layout == FibreLayout::random
                            ? geo.random.volume_fraction * geo.size[0] * geo.size[1] /
                                  (std::numbers::pi * geo.random.radius_mean * geo.random.radius_mean)
                            : static_cast<double>(geo.fibres.size());
  if (fibres > max_rve_fibres)
    c.fail("geometry", geo.layout == FibreLayout::random ? "volume_fraction" : "size", "",
           "the RVE would have about " + std::to_string(std::llround(std::min(fibres, 1e18))) +
               " fibres, more than the limit " + std::to_string(max_rve_fibres) +
               " (its mesh: about two minutes at the limit, growing as N^1.4): a smaller size or larger fibres");
  // The mesh budget: elements of edge h (rve_element_size), about 2.3 area / h² triangles, (2k)²
  // more nodes per corner node for p2.
  const double h = rve_element_size(r_mean, geo.degree);
  const double nodes = rve_node_estimate(geo.size[0], geo.size[1], r_mean, geo.degree, geo.element);
  if (nodes > max_mesh_nodes) {
    std::ostringstream s;
    s << "the mesh would have about " << static_cast<long long>(nodes)
      << " nodes (element size pi r / (4 degree) = " << h << " over " << geo.size[0] << " x " << geo.size[1]
      << "), more than the limit " << max_mesh_nodes;
    c.fail("geometry", "degree", std::to_string(geo.degree), s.str());
  }
  if (scene.load.boundary != Boundary::periodic)
    c.fail("load", "boundary", to_string(scene.load.boundary),
           "an RVE (size = [Lx, Ly]) is periodic: boundary = \"periodic\"");
}

}  // namespace

double rve_element_size(double mean_radius, int degree) { return std::numbers::pi * mean_radius / (4 * degree); }

void check_load_strain(const Scene& scene, double stress_norm, const std::string& what) {
  const double strain = stress_norm / std::min(scene.fibre.E, scene.matrix.E);
  if (!(strain <= max_load_strain))
    throw InputError(what + ": a stress of " + shortest(stress_norm) + " strains the softer phase (E = " +
                     shortest(std::min(scene.fibre.E, scene.matrix.E)) + ") by about " + formatted("%.3g", strain) +
                     ", beyond " + shortest(max_load_strain) + ": no finite answer in doubles");
}

double rve_default_min_gap(double mean_radius, int degree) {
  return 2 * rve_element_size(mean_radius, degree) / rve_narrowest_gap_divisor;
}

double rve_node_estimate(double Lx, double Ly, double mean_radius, int degree, Element element) {
  const double h = rve_element_size(mean_radius, degree);
  return 1.2 * Lx * Ly / (h * h) * (element == Element::p2 ? 4 : 1);
}

namespace {

void validate_geometry(const Checker& c, const Scene& scene) {
  const Geometry& geo = scene.geometry;
  if (geo.rve()) return validate_rve(c, scene);
  c.reals(
      "geometry", "cells", {double(geo.cells[0]), double(geo.cells[1])}, [](double v) { return v >= 1 && v <= 4096; },
      "an array of 2 numbers, each an integer in [1, 4096]");
  c.real("geometry", "cell_size", geo.cell_size, length_in_range,
         "cell_size in [1e-50, 1e50] (the cell's area, its law's volume, within 1e±100)");
  c.real("geometry", "fibre_radius", geo.fibre_radius, positive, "fibre_radius > 0");
  c.reals("geometry", "fibre_offset", {geo.fibre_offset[0], geo.fibre_offset[1]}, finite,
          "an array of 2 numbers, each a finite number");
  c.integer("geometry", "degree", geo.degree, 1, 256);
  // A bound on the mesh a scene may ask for: beyond it the mesh stage would allocate (and the
  // solver factorise) more than any machine holds; 16m² + 16m + 1 nodes per cell with m = k for
  // p1 and m = 2k for p2.
  const double m = double(geo.degree) * element_order(geo.element);
  const double nodes = double(geo.cells[0]) * geo.cells[1] * (16.0 * m * m + 16.0 * m + 1);
  if (nodes > max_mesh_nodes) {
    std::ostringstream s;
    s << "the mesh would have " << static_cast<long long>(nodes) << " nodes (" << geo.cells[0] << " x " << geo.cells[1]
      << " cells at degree " << geo.degree << " with " << to_string(geo.element)
      << " elements: 16m^2 + 16m + 1 per cell, m = k for p1, 2k for p2), more than the limit " << max_mesh_nodes;
    c.fail("geometry", "cells", shortest({double(geo.cells[0]), double(geo.cells[1])}), s.str());
  }
  const double half = geo.cell_size / 2;
  for (int d = 0; d < 2; ++d) {
    if (!(geo.fibre_radius + std::abs(geo.fibre_offset[d]) < half)) {
      std::ostringstream s;
      s << "the fibre touches or crosses its cell's edge: need fibre_radius + |fibre_offset[" << d
        << "]| = " << geo.fibre_radius + std::abs(geo.fibre_offset[d]) << " < cell_size/2 = " << half;
      c.fail("geometry", "fibre_radius", shortest(geo.fibre_radius), s.str());
    }
  }
}

void validate_materials_and_interface(const Checker& c, const Scene& scene) {
  for (const auto& [name, material] :
       {std::pair<const char*, const Material*>{"fibre", &scene.fibre}, {"matrix", &scene.matrix}}) {
    const Material* m = material;  // a variable, not a binding: lambdas capture it (C++20 and Clang 15)
    c.real(name, "E", m->E, positive, "E > 0");
    // Expansion coefficients of real solids lie within ±1e-4 per kelvin (polymers about 6e-5,
    // carbon fibres about −1e-6 along and 1e-5 across); ±1e-3 leaves room and refuses a
    // coefficient given in ppm or percent.
    const auto expansion = [](double v) { return std::abs(v) <= 1e-3; };
    c.real(name, "alpha", m->alpha, expansion, "|alpha| <= 1e-3 per kelvin (a strain per kelvin, not ppm)");
    c.real(name, "alpha_L", m->alpha_L, expansion, "|alpha_L| <= 1e-3 per kelvin (a strain per kelvin, not ppm)");
    if (!m->axial) {
      c.real(
          name, "nu", m->nu, [](double v) { return v > -1 && v < 0.5; }, "-1 < nu < 0.5");
      continue;
    }
    // Transversely isotropic: the compliance positive definite, i.e. E_T, E_L, G_LT > 0,
    // −1 < ν_TT < 1 and 1 − ν_TT − 2 ν_LT² E_T/E_L > 0.
    c.real(
        name, "nu", m->nu, [](double v) { return v > -1 && v < 1; }, "-1 < nu < 1 (nu_TT, the transverse plane's)");
    c.real(name, "E_L", m->E_L, positive, "E_L > 0");
    c.real(name, "G_LT", m->G_LT, positive, "G_LT > 0");
    c.real(
        name, "nu_LT", m->nu_LT, [m](double) { return m->E_L > 0 && m->compliance_margin() > 0; },
        "1 - nu - 2 nu_LT^2 E/E_L > 0 (the phase's compliance positive definite)");
  }

  c.real("interface", "normal_strength", scene.interface.normal_strength, non_negative,
         "normal_strength >= 0 (0: no adhesion)");
  c.real("interface", "tangential_strength", scene.interface.tangential_strength, non_negative,
         "tangential_strength >= 0 (0: no adhesion)");
}

void validate_load(const Checker& c, const Scene& scene) {
  c.real(
      "load", "delta_T", scene.load.delta_T, [](double v) { return std::abs(v) <= 1000; },
      "|delta_T| <= 1000 (kelvin, from the stress-free temperature)");
  if (scene.load.delta_T != 0)
    for (const auto& [name, material] :
         {std::pair<const char*, const Material*>{"fibre", &scene.fibre}, {"matrix", &scene.matrix}})
      if (!material->expands)
        c.fail("load", "delta_T", shortest(scene.load.delta_T),
               std::string("a temperature change needs both phases' expansion: give [") + name + "] alpha");
  const auto& bf = scene.load.body_force;
  c.reals("load", "body_force", {bf[0], bf[1]}, finite, "an array of 2 numbers, each a finite number");
  // A body force is carried only by the symmetry edges' reactions, and the debond onset formula
  // s* = bound/λ(σ̄) assumes λ linear in σ̄ alone: refuse the combinations where either would
  // silently be wrong.
  if (bf[0] != 0 || bf[1] != 0) {
    if (scene.load.boundary != Boundary::symmetry)
      c.fail("load", "body_force", "",
             "a body force needs boundary = \"symmetry\" (the traction and periodic "
             "boundaries have no reactions to carry its resultant)");
    if (scene.interface.has_adhesion())
      c.fail("load", "body_force", "",
             "a body force cannot be combined with adhesion (the debond onset is "
             "computed for the macro stress alone)");
  }
}

void validate_sweep_and_solver(const Checker& c, const Scene& scene) {
  const SweepSettings& sw = scene.sweep;
  if (sw.directions_deg.empty()) c.fail("sweep", "directions_deg", "[]", "must be an array of at least 1 numbers");
  c.reals(
      "sweep", "directions_deg", sw.directions_deg, [](double v) { return v >= -360 && v <= 360; },
      "an array of at least 1 numbers, each in [-360, 360] degrees");
  if (sw.magnitudes.empty()) c.fail("sweep", "magnitudes", "[]", "must be an array of at least 1 numbers");
  c.reals(
      "sweep", "magnitudes", sw.magnitudes, [](double v) { return v != 0; },
      "an array of at least 1 numbers, each non-zero");
  const double softer = std::min(scene.fibre.E, scene.matrix.E);
  for (const double m : sw.magnitudes)
    if (!(std::abs(m) / softer <= max_load_strain))
      c.fail("sweep", "magnitudes", shortest(m),
             "out of range: it strains the softer phase (E = " + shortest(softer) + ") beyond " +
                 shortest(max_load_strain) + " (no finite answer in doubles)");
  for (const auto& t : sw.stress_directions)
    if (!(std::isfinite(t[0]) && std::isfinite(t[1]) && std::isfinite(t[2])) || (t[0] == 0 && t[1] == 0 && t[2] == 0))
      c.fail("sweep", "stress_directions", shortest(std::vector<double>(t.begin(), t.end())),
             "must be an array of [sxx, syy, sxy] stress tensors, each finite and not all zero");
  c.integer("sweep", "sphere", sw.sphere, 0, 100000);
  if (sw.sphere > 0 && scene.load.boundary == Boundary::symmetry)
    c.fail("sweep", "sphere", std::to_string(sw.sphere),
           "the symmetry boundary carries no shear stress; a sphere of stress directions needs boundary = "
           "\"traction\" or \"periodic\"");
  c.reals(
      "sweep", "eps33", sw.eps33, [](double v) { return v != 0 && v >= -0.1 && v <= 0.1; },
      "an array of strains along the fibres, each non-zero and in [-0.1, 0.1]");
  if (!sw.eps33.empty() && scene.load.macro != Macro::full)
    c.fail("sweep", "eps33", shortest(sw.eps33),
           "paths with a strain along the fibres need [load] macro = \"full\" (the transverse law has no ε33)");
  if (sw.gamma.size() > 100)
    c.fail("sweep", "gamma", std::to_string(sw.gamma.size()) + " shears",
           "at most 100 (each copies every uniaxial path)");
  for (const auto& g : sw.gamma)
    if (!(std::isfinite(g[0]) && std::isfinite(g[1])) || (g[0] == 0 && g[1] == 0) || std::abs(g[0]) > 0.1 ||
        std::abs(g[1]) > 0.1)
      c.fail("sweep", "gamma", shortest(std::vector<double>(g.begin(), g.end())),
             "must be an array of [gamma_xz, gamma_yz] shears along the fibres, each in [-0.1, 0.1] and not both 0");
  if (!sw.gamma.empty() && (scene.load.macro != Macro::full || scene.load.boundary != Boundary::periodic))
    c.fail("sweep", "gamma", std::to_string(sw.gamma.size()) + " shears",
           "paths with a shear along the fibres need [load] macro = \"full\" and boundary = \"periodic\"");
  c.real(
      "sweep", "fuse_tolerance", sw.fuse_tolerance, [](double v) { return v > 0 && v < 1; }, "0 < fuse_tolerance < 1");

  const SolverSettings& so = scene.solver;
  c.real(
      "solver", "tolerance", so.tolerance, [](double v) { return v >= 1e-15 && v < 1; }, "1e-15 <= tolerance < 1");
  c.integer("solver", "max_outer_iterations", so.max_outer_iterations, 1, 100000);
  c.integer("solver", "max_operator_applications", so.max_operator_applications, 1, 1000000000L);
  c.real(
      "solver", "rho_factor", so.rho_factor, [](double v) { return v > 0 && v <= 1e6; }, "0 < rho_factor <= 1e6");
  c.real(
      "solver", "rho_growth", so.rho_growth, [](double v) { return v >= 1 && v <= 1e3; }, "1 <= rho_growth <= 1e3");
  c.integer("solver", "rho_patience", so.rho_patience, 1, 100000);
  c.real(
      "solver", "Gamma", so.Gamma, [](double v) { return v > 0 && v <= 1e3; }, "0 < Gamma <= 1e3");
  c.integer("solver", "max_debond_rounds", so.max_debond_rounds, 1, 1000000);
  if (so.subdomain_dofs != 0 && (so.subdomain_dofs < 100 || so.subdomain_dofs > 10000000))
    c.fail("solver", "subdomain_dofs", std::to_string(so.subdomain_dofs),
           "out of range: 0 (an RVE's matrix whole) or an integer in [100, 10000000]");
}

// A resolved block must be held against every rigid motion (core/edge_loads.hpp).
void validate_edges(const Scene& scene) {
  const Geometry& geo = scene.geometry;
  // By its edges and by supports on the matrix: a support inside a fibre holds that fibre only
  // (without adhesion the matrix would float free of it; with adhesion, once the bonds break).
  if (scene.load.boundary == Boundary::edges) {
    const double a = geo.cell_size, r = geo.fibre_radius;
    const auto on_matrix = [&](const Eigen::Vector2d& p) {
      const int i = std::clamp(static_cast<int>(std::floor(p.x() / a)), 0, geo.cells[0] - 1);
      const int j = std::clamp(static_cast<int>(std::floor(p.y() / a)), 0, geo.cells[1] - 1);
      const Eigen::Vector2d centre((i + 0.5) * a + geo.fibre_offset[0], (j + 0.5) * a + geo.fibre_offset[1]);
      return (p - centre).norm() >= r * (1 - 1e-9);
    };
    const std::string free = free_rigid_motion(scene.load.edge_loads, geo.cells[0] * a, geo.cells[1] * a, on_matrix);
    if (!free.empty())
      throw InputError((scene.file.empty() ? std::string("scene") : scene.file.string()) +
                       ": the edges and the supports on the matrix leave a rigid-body motion free, " + free +
                       " (a support inside a fibre holds that fibre only)");
  }
}

}  // namespace

void validate(const Scene& scene) {
  const Checker c(scene);
  validate_geometry(c, scene);
  validate_materials_and_interface(c, scene);
  validate_load(c, scene);
  validate_sweep_and_solver(c, scene);
  validate_edges(scene);
}

std::vector<std::string> scene_warnings(const Scene& scene) {
  // Triangles lock as ν → 0.5 in plane strain: the volumetric constraint over-stiffens the mesh.
  // Measured: the bonded near-void modulus normalised by E_m/(1−ν_m²), which is ν-independent
  // in the continuum (docs/method.md §18), at degree 3: linear triangles drift by 3 %
  // at ν_m = 0.45 (0.4 % at 0.3); quadratic ones by 0.05 % at 0.45, 0.3 % at 0.499 and 0.9 % at
  // 0.4999. So p1 is warned about from 0.45 on, p2 from 0.499 on.
  const bool linear = scene.geometry.element == Element::p1;
  const double threshold = linear ? 0.45 : 0.499;
  std::vector<std::string> warnings;
  for (const auto& [name, material] :
       {std::pair<const char*, const Material*>{"fibre", &scene.fibre}, {"matrix", &scene.matrix}}) {
    // A transversely isotropic phase locks by the same ratio of its plane-strain bulk modulus to
    // its transverse shear modulus, k/G_TT = (1 + ν)/(1 − ν − 2 ν_LT² E/E_L), which is
    // 1/(1 − 2ν) for an isotropic one: warned about where it passes the isotropic phase's at the
    // threshold.
    const Material& m = *material;
    const bool nearly_incompressible =
        !m.axial ? m.nu >= threshold : (1 + m.nu) / m.compliance_margin() >= 1 / (1 - 2 * threshold);
    if (nearly_incompressible) {
      const auto at = scene.written.find(std::string(name) + ".nu");
      std::ostringstream w;
      w << (at != scene.written.end() ? at->second.where
            : scene.file.empty()      ? "scene"
                                      : scene.file.string())
        << ": [" << name << "] nu = " << material->nu << ": nearly incompressible; "
        << (linear ? "linear triangles lock, so moduli come out too stiff (about 3 % at nu = 0.45, more towards "
                     "0.5); use element = \"p2\" or compare with a higher degree before trusting them"
                   : "quadratic triangles stiffen slightly (about 0.3 % at nu = 0.499, 1 % at 0.4999); compare "
                     "with a higher degree before trusting them");
      warnings.push_back(w.str());
    }
  }
  return warnings;
}

Constituents constituents(const Scene& scene) {
  const double r = scene.geometry.fibre_radius, a = scene.geometry.cell_size;
  Constituents c{scene.fibre.E, scene.fibre.nu, scene.matrix.E, scene.matrix.nu, std::numbers::pi * r * r / (a * a), a};
  set_axes(c, scene.fibre, scene.matrix);
  return c;
}

void set_axes(Constituents& c, const Material& fibre, const Material& matrix) {
  c.fibre_E_L = fibre.axial_E(), c.fibre_nu_LT = fibre.axial_nu(), c.fibre_G_LT = fibre.axial_G();
  c.matrix_E_L = matrix.axial_E(), c.matrix_nu_LT = matrix.axial_nu(), c.matrix_G_LT = matrix.axial_G();
}

Constituents with_isotropic_axes(Constituents c) {
  set_axes(c, {c.fibre_E, c.fibre_nu}, {c.matrix_E, c.matrix_nu});
  return c;
}

std::string solver_options_text(const Scene& scene) {
  const auto& s = scene.solver;
  std::ostringstream o;
  o.precision(17);
  o << "tolerance=" << s.tolerance << "; max_outer_iterations=" << s.max_outer_iterations
    << "; max_operator_applications=" << s.max_operator_applications << "; rho_factor=" << s.rho_factor
    << "; rho_growth=" << s.rho_growth << "; rho_patience=" << s.rho_patience << "; Gamma=" << s.Gamma
    << "; max_debond_rounds=" << s.max_debond_rounds << "; preconditioner=" << to_string(s.preconditioner)
    << "; dual_operator=" << to_string(s.dual_operator) << "; fuse_tolerance=" << scene.sweep.fuse_tolerance;
  return o.str();
}

}  // namespace dualcell
