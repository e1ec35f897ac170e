#pragma once
// The scene: one TOML file shared by every stage (mesh, solve, sweep, fit, export).
// Reading (parse_scene) checks the TOML, the tables, the keys and their types; validate()
// checks every value's range and the combinations of keys, for scenes read from a file and for
// scenes built in code alike, with the same one-line messages naming the file, the line, the
// key, the value and the allowed range. All keys and their defaults: docs/reference/scene-keys.md.
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/edge_loads.hpp"
#include "core/fields.hpp"

namespace dualcell {

// A phase's linear elastic material (docs/theory/model.md §1): isotropic (E, ν), or transversely
// isotropic about the fibres' axis z (`axial`): E and ν are then those of the transverse plane
// (E_T, ν_TT), and along the axis E_L, ν_LT (the transverse contraction per unit axial strain
// under an axial stress: S13 = −ν_LT/E_L) and G_LT (the shear modulus of the planes that contain
// the axis: the shear along the fibres). An isotropic phase is the special case E_L = E,
// ν_LT = ν, G_LT = E/(2(1 + ν)), which the accessors give.
struct Material {
  double E = 0;
  double nu = 0;
  bool axial = false;  // transversely isotropic: E_L, nu_LT, G_LT given
  double E_L = 0, nu_LT = 0, G_LT = 0;
  // Thermal expansion (strain per kelvin): alpha across the fibres (the transverse plane's),
  // alpha_L along them (= alpha unless the phase is transversely isotropic and gives its own).
  bool expands = false;  // alpha given
  double alpha = 0, alpha_L = 0;

  double axial_E() const { return axial ? E_L : E; }
  double axial_nu() const { return axial ? nu_LT : nu; }
  double axial_G() const { return axial ? G_LT : E / (2 * (1 + nu)); }
  // m = 1 − ν − 2 ν_LT² E/E_L. With E, E_L, G_LT > 0 and ν > −1 the compliance is positive
  // definite exactly when m > 0 (isotropic: m = (1 − 2ν)(1 + ν)), and the plane-strain bulk
  // modulus over the transverse shear modulus, what locks in a nearly incompressible phase, is
  // (1 + ν)/m (isotropic: 1/(1 − 2ν)).
  double compliance_margin() const { return 1 - nu - 2 * axial_nu() * axial_nu() * E / axial_E(); }
};

// Finite element of the mesh (docs/method.md §3): linear 3-node or quadratic 6-node triangles.
enum class Element { p1, p2 };
const char* to_string(Element e);
// Nodes per triangle edge minus one: 1 for p1, 2 for p2 (a p2 mesh of degree k has the nodes of
// the p1 mesh of degree 2k).
inline int element_order(Element e) { return e == Element::p1 ? 1 : 2; }

// Random fibres of a periodic RVE (docs/method.md §16b, rve/microstructure.hpp): radii normal
// (mean, standard deviation), placed to the volume fraction keeping min_gap between fibres and
// to the edges they do not cross (min_gap also checks a list of fibres), reproducible from seed.
struct RandomFibres {
  double volume_fraction = 0.5;
  double radius_mean = 0.05, radius_sd = 0;
  double min_gap = 0;
  std::uint64_t seed = 1;
  // Shaking sweeps (every fibre one move) allowed while fibres remain to be placed.
  int max_shake_sweeps = 20000;
};

// How the fibres are laid out: one per square cell of a block (the mapped mesher, mesh/mesh.hpp),
// or a periodic RVE of a given size whose fibres are a list or random (meshed by gmsh,
// rve/mesher.hpp).
enum class FibreLayout { cells, list, random };
const char* to_string(FibreLayout l);

// One fibre of a list: its centre and its radius.
struct FibreCircle {
  std::array<double, 2> centre{0, 0};
  double radius = 0;
};

struct Geometry {
  FibreLayout layout = FibreLayout::cells;
  std::array<double, 2> size{0, 0};          // Lx, Ly of an RVE (layout list or random)
  std::vector<FibreCircle> fibres;           // layout list
  RandomFibres random;                       // layout random; its min_gap also for a list
  std::array<int, 2> cells{1, 1};            // ex, ey
  double cell_size = 1.0;                    // edge length of one square cell
  double fibre_radius = 0.3;                 // r
  std::array<double, 2> fibre_offset{0, 0};  // fibre centre minus cell centre
  int degree = 1;                            // k: 4k+1 element corners on each cell edge (docs/method.md §2)
  // p2 by default: on the accuracy study's cell it reaches a given error far sooner than p1
  // (docs/results/accuracy.md).
  Element element = Element::p2;

  bool rve() const { return layout != FibreLayout::cells; }
  // The block's (or the RVE's) width and height.
  double width() const { return rve() ? size[0] : cells[0] * cell_size; }
  double height() const { return rve() ? size[1] : cells[1] * cell_size; }
};

// The element size of an RVE's mesh, h = π r̄/(4k) with r̄ the fibres' mean radius and k the
// degree: the edge of a mapped cell's rim elements at the same degree (docs/method.md §16b). The
// mesher takes the mean of the fibres it meshes; the scene's check, which runs before random
// fibres exist, the scene's mean (a list's mean, or the nominal mean of random radii, which the
// volume fraction then scales a little).
double rve_element_size(double mean_radius, int degree);
// The narrowest gap (between fibres, to an edge, a sliver an edge cuts) the RVE mesher meshes:
// h/50, across which its finest elements (h/10) are still no slivers (rve/mesher.cpp).
inline constexpr double rve_narrowest_gap_divisor = 50;
// The gap a random RVE keeps when its scene gives no min_gap: twice the narrowest the mesher
// meshes at the scene's degree, so that every drawn RVE meshes (the volume fraction scales the
// drawn radii, and h with them, by a few per cent).
double rve_default_min_gap(double mean_radius, int degree);
// The nodes of an RVE's mesh at that element size over Lx × Ly: about 1.2 per h² for p1, 4 times
// that for p2 (the mesh budget, checked against max_mesh_nodes before gmsh runs).
double rve_node_estimate(double Lx, double Ly, double mean_radius, int degree, Element element);

// Interface strengths per unit interface length (force/length); 0 = no adhesion (docs/method.md §1, §4).
struct Interface {
  double normal_strength = 0;
  double tangential_strength = 0;
  bool has_adhesion() const { return normal_strength > 0 || tangential_strength > 0; }
};

// The boundary of the block (docs/method.md §12): a macro stress σ̄ through symmetry planes, as
// tractions on all four sides, or through periodicity; or `edges`: a structure of resolved cells
// with conditions per edge (core/edge_loads.hpp), loaded in steps by a load factor.
enum class Boundary { symmetry, traction, periodic, edges };
const char* to_string(Boundary b);

// Which macro components a cell's law carries (docs/method.md §3a): the transverse plane strain
// (εxx, εyy, γxy), or also the strain ε33 along the fibres (generalised plane strain), whose
// column the exact law then condenses too.
enum class Macro { transverse, full };

struct Load {
  Boundary boundary = Boundary::symmetry;
  Macro macro = Macro::transverse;
  std::array<double, 2> body_force{0, 0};  // force per unit area, both materials
  // The temperature change ΔT (kelvin) from the stress-free state (the cure), applied before
  // any load and held along every path; needs both phases' alpha (docs/theory/model.md §1a).
  double delta_T = 0;
  EdgeLoads edge_loads;  // Boundary::edges only
};

struct SweepSettings {
  std::vector<double> directions_deg{0.0, 90.0};
  std::vector<double> magnitudes{-1.0, 1.0};  // signed macro-stress values
  // General load paths besides the uniaxial ones: stress tensors (σxx, σyy, σxy), normalised
  // to unit Frobenius norm, each swept with the same signed magnitudes.
  std::vector<std::array<double, 3>> stress_directions;
  // N > 0: N more paths along directions spread evenly over the unit sphere of
  // (σxx, σyy, √2σxy) (a Fibonacci point set), each loaded along +N only (the set covers both
  // signs). Without adhesion one magnitude per direction (the largest |magnitude|): the response
  // is positively homogeneous, ε(sσ̄) = s ε(σ̄); with adhesion every |magnitude|.
  int sphere = 0;
  // Strains ε33 along the fibres, each held along one more copy of every uniaxial path
  // (directions_deg, both signs); only with [load] macro = "full" (docs/method.md §16a).
  std::vector<double> eps33;
  // Shears Γ = (γxz, γyz) along the fibres, each held along one more copy of every uniaxial path;
  // only with [load] macro = "full" on the periodic boundary (docs/method.md §16a).
  std::vector<std::array<double, 2>> gamma;
  double fuse_tolerance = 1e-3;  // relative load bracket of the debond jump
};

// Preconditioner of the dual operator F (docs/method.md §8): none, the
// lumped one Σ B_i K_i B_iᵀ, or the Dirichlet one Σ B_i S_i B_iᵀ (S_i the Schur complement of
// K_i on its boundary), both with stiffness-weighted rows; applied by MPRGP in the free face.
enum class Preconditioner { none, lumped, dirichlet };
const char* to_string(Preconditioner p);

// How each subdomain applies its part of F = Σ B_s K_s⁺ B_sᵀ (docs/method.md §6a): implicit, two
// sparse triangular sweeps with the factor of K_s per application; explicit, one dense product
// with F_s = B_s K_s⁺ B_sᵀ, formed once from the factor's trailing block (the boundary's Schur
// complement); auto, per subdomain, by the cost model in feti/operator_cost.hpp.
enum class DualOperator { automatic, implicit, explicit_ };
const char* to_string(DualOperator o);

struct SolverSettings {
  double tolerance = 1e-8;                  // relative KKT tolerance of the dual QP
  int max_outer_iterations = 200;           // SMALBE outer iterations
  long max_operator_applications = 200000;  // applications of F = B K+ B^T
  double rho_factor = 1.0;                  // SMALBE penalty rho = rho_factor * ||F||
  double rho_growth = 10.0;                 // SMALBE penalty safeguard factor; 1 = plain SMALBE-M
  int rho_patience = 5;                     // ... applied after this many slow outer iterations in a row
  double Gamma = 1.0;                       // MPRGP proportioning parameter
  int max_debond_rounds = 1000;             // break / re-solve rounds per load (docs/method.md §11)
  Preconditioner preconditioner = Preconditioner::none;
  DualOperator dual_operator = DualOperator::automatic;
  // 0 (the default): an RVE's matrix is one subdomain; else it is split by METIS into subdomains
  // of about this many DOFs (rve/mesher.hpp). Each fibre piece is a subdomain of its own; the
  // mapped block has one matrix subdomain per cell. Why whole: the pieces of a matrix cut between
  // fibres are webs of thin ligaments, floppy on their own, and their soft modes set ‖F‖; on the
  // contact ladder (tools/bench_contact.py, 64 fibres) cutting at 1 500 DOFs cost 4.6× the F
  // applications of the whole matrix bonded and 25× in contact (docs/method.md §16b).
  int subdomain_dofs = 0;
};

struct WrittenKey {
  std::string where;  // "file:line:column"
  std::string value;  // as written
};

struct Scene {
  std::filesystem::path file;  // where it was read from ("<string>" when parsed from text)
  std::string text;            // the scene file verbatim, for provenance
  std::string material_file;   // resolved path of `material = "..."`, empty when inline
  std::string material_text;   // that file verbatim
  Geometry geometry;
  Material fibre;
  Material matrix;
  Interface interface;
  Load load;
  SweepSettings sweep;
  SolverSettings solver;
  // Advice that does not stop a stage (printed as "<stage>: warning: ..."), e.g. locking.
  std::vector<std::string> warnings;
  // Where each key was written, for a scene read from a file ("geometry.degree" → where
  // "scene.toml:5:10", value "3" as written); empty for a scene built in code.
  std::map<std::string, WrittenKey> written;

  int n_cells() const { return geometry.cells[0] * geometry.cells[1]; }
};

// What the fit, the exports and structures need of a scene: the constituents and the fibre
// volume fraction V_f = π r² / a² (out-of-plane constants by the rule of mixtures), and the
// cell size a (a structure's cells are this size).
struct Constituents {
  double fibre_E = 0, fibre_nu = 0, matrix_E = 0, matrix_nu = 0;
  double fibre_volume_fraction = 0;
  double cell_size = 1;
  // Along the fibres' axis (Material::axial_E, axial_nu, axial_G; an isotropic phase's from E, ν).
  double fibre_E_L = 0, fibre_nu_LT = 0, fibre_G_LT = 0, matrix_E_L = 0, matrix_nu_LT = 0, matrix_G_LT = 0;
};
Constituents constituents(const Scene& scene);
// The constituents along the axis of two isotropic phases, from their E and ν (a file written
// before the phases could be transversely isotropic).
Constituents with_isotropic_axes(Constituents c);
// The constituents' along-axis constants (fibre_E_L, ...) set from two phases.
void set_axes(Constituents& c, const Material& fibre, const Material& matrix);

// "tolerance=1e-08; max_outer_iterations=200; ...; fuse_tolerance=0.001": every setting that
// changes a sweep's numbers, recorded in sweep.h5 and law.h5 and part of the journal's key.
std::string solver_options_text(const Scene& scene);

// Their attribute names in sweep.h5 (root) and law.h5 (/law).
inline constexpr Field<Constituents, double> constituent_fields[] = {
    {"fibre_E", &Constituents::fibre_E},
    {"fibre_nu", &Constituents::fibre_nu},
    {"matrix_E", &Constituents::matrix_E},
    {"matrix_nu", &Constituents::matrix_nu},
    {"fibre_volume_fraction", &Constituents::fibre_volume_fraction},
    {"cell_size", &Constituents::cell_size},
};
// The constituents along the fibres' axis: written beside them; a file without them (written
// before the phases could be transversely isotropic) has isotropic phases.
inline constexpr Field<Constituents, double> axial_constituent_fields[] = {
    {"fibre_E_L", &Constituents::fibre_E_L},       {"fibre_nu_LT", &Constituents::fibre_nu_LT},
    {"fibre_G_LT", &Constituents::fibre_G_LT},     {"matrix_E_L", &Constituents::matrix_E_L},
    {"matrix_nu_LT", &Constituents::matrix_nu_LT}, {"matrix_G_LT", &Constituents::matrix_G_LT},
};

// Largest mesh a scene may ask for (nodes of all subdomains, dim u = 2 × nodes): 3×3 cells at
// degree 256 or 100×100 at degree 6 fit, 4096×4096 at degree 256 (10^13 nodes) does not.
inline constexpr long max_mesh_nodes = 10'000'000;
// The largest macro stress a solve takes, as the strain it causes: |σ|∞ / min(E_fibre, E_matrix)
// at most this. Beyond it the solver's products of forces and displacements overflow doubles and
// no finite answer exists; a small-strain law is meaningless long before.
inline constexpr double max_load_strain = 1e100;
// Refuses (InputError, naming `what`) a stress beyond max_load_strain for the scene's phases.
void check_load_strain(const Scene& scene, double stress_norm, const std::string& what);
// The most fibres an RVE may have: gmsh meshes 6 400 in about a minute here and its time grows
// as N^1.4 (10 000: about two minutes; 160 000 would take over an hour).
inline constexpr long max_rve_fibres = 10'000;
// The range of a law's cell size (any unit) that a structure of homogeneous cells takes: its
// positions (supports, loads, the watch point) are written in that unit, and beyond this range
// they and the node tolerance (node_reach: 1e-9 of the structure's size) underflow or lose
// every digit.
inline constexpr double min_structure_cell_size = 1e-12, max_structure_cell_size = 1e12;

// Every range and combination of keys; an InputError naming the first violation. The stages,
// the solver (feti::FetiSetup) and the studies call it on every scene they use.
void validate(const Scene& scene);
// Advice for a valid scene that does not stop a stage (e.g. near-incompressible materials).
std::vector<std::string> scene_warnings(const Scene& scene);

// Reads and validates a scene file; relative material paths resolve against its folder.
Scene load_scene(const std::filesystem::path& file);
// Same from text; `file` is used in messages and to resolve relative paths.
Scene parse_scene(std::string_view text, const std::filesystem::path& file);

}  // namespace dualcell
