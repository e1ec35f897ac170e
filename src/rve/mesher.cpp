#include "rve/mesher.hpp"

#include <metis.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <set>
#include <unordered_map>

#include "core/edge_loads.hpp"
#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/text.hpp"
#include "core/union_find.hpp"
#include "rve/disk_grid.hpp"
#include "rve/gmsh_model.hpp"

namespace dualcell::rve {

namespace {

using Clock = std::chrono::steady_clock;

// A periodic image of a fibre that reaches into the rectangle: one fibre piece once meshed.
struct Image {
  int fibre = 0;
  Eigen::Vector2d centre;
  double radius = 0;
};

std::vector<Image> images_in(const Microstructure& m) {
  std::vector<Image> out;
  for (int k = 0; k < static_cast<int>(m.fibres.size()); ++k)
    for (int iy = -1; iy <= 1; ++iy)
      for (int ix = -1; ix <= 1; ++ix) {
        const Fibre& f = m.fibres[k];
        const Eigen::Vector2d c = f.centre + Eigen::Vector2d(ix * m.Lx, iy * m.Ly);
        if (c.x() + f.radius > 0 && c.x() - f.radius < m.Lx && c.y() + f.radius > 0 && c.y() - f.radius < m.Ly)
          out.push_back({k, c, f.radius});
      }
  return out;
}

// The smallest element is h/smallest_element_divisor: the size field refines narrow gaps down to
// it and no further. A gap narrower than h/rve_narrowest_gap_divisor (core/scene.hpp) is refused:
// its elements, that smallest size across a gap five times narrower, would be slivers.
constexpr double smallest_element_divisor = 10;

// The mesh size at a point: h, or the sum of the distances to the two nearest fibre surfaces
// where that is smaller (a narrow gap), not below h/smallest_element_divisor.
// Only surfaces nearer than h matter (two of them sum below h or the size is h), so only circles
// whose centre lies within r_max + h: the circles (every periodic image) are binned by a DiskGrid
// of that reach, and a call looks at its 3 × 3 bins, not at every fibre (gmsh calls it for every
// node it places: that made meshing quadratic in the fibres, 29 s at 400 and 440 s at 1600).
class SizeField {
 public:
  SizeField(const Microstructure& m, double h)
      : h_(h), grid_(-m.Lx, -m.Ly, 3 * m.Lx, 3 * m.Ly, largest_radius(m) + h, false) {
    for (const Fibre& f : m.fibres)
      for (int iy = -1; iy <= 1; ++iy)
        for (int ix = -1; ix <= 1; ++ix) {
          circles_.push_back({f.centre + Eigen::Vector2d(ix * m.Lx, iy * m.Ly), f.radius});
          grid_.insert(static_cast<int>(circles_.size()) - 1, circles_.back().centre);
        }
  }
  double operator()(double x, double y) const {
    double d1 = std::numeric_limits<double>::infinity(), d2 = d1;
    const Eigen::Vector2d p(x, y);
    grid_.near(p, [&](int k) {
      const Fibre& c = circles_[static_cast<std::size_t>(k)];
      const double d = std::abs((p - c.centre).norm() - c.radius);
      if (d < d1)
        d2 = d1, d1 = d;
      else if (d < d2)
        d2 = d;
    });
    return std::min(h_, std::max(d1 + d2, h_ / smallest_element_divisor));
  }

 private:
  static double largest_radius(const Microstructure& m) {
    double r = 0;
    for (const Fibre& f : m.fibres) r = std::max(r, f.radius);
    return r;
  }
  double h_;
  DiskGrid grid_;
  std::vector<Fibre> circles_;
};

// The matrix triangles' parts: METIS on the dual graph (triangles sharing an edge) into
// n_parts, then each part's connected pieces (a METIS part need not be connected), numbered in
// order of their first triangle. Returns the subdomain of every triangle and their count.
std::pair<std::vector<int>, int> split_matrix(const std::vector<std::vector<std::size_t>>& triangles, int n_parts) {
  const auto n = static_cast<idx_t>(triangles.size());
  std::vector<idx_t> part(n, 0);
  std::unordered_map<std::size_t, idx_t> compact;
  for (const auto& t : triangles)
    for (int c = 0; c < 3; ++c) compact.emplace(t[c], static_cast<idx_t>(compact.size()));
  if (n_parts > 1 && n > n_parts) {
    std::vector<idx_t> eptr(n + 1), eind(3 * n), npart(compact.size());
    for (idx_t e = 0; e < n; ++e) {
      eptr[e + 1] = 3 * (e + 1);
      for (int c = 0; c < 3; ++c) eind[3 * e + c] = compact.at(triangles[e][c]);
    }
    idx_t ne = n, nn = static_cast<idx_t>(compact.size()), ncommon = 2, nparts = n_parts, objval = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;  // the same split on every run
    if (METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr, &ncommon, &nparts, nullptr, options,
                           &objval, part.data(), npart.data()) != METIS_OK)
      throw InputError("METIS could not split the matrix into " + std::to_string(n_parts) + " parts");
  }
  // Connected pieces of each part: triangles of one part sharing an edge, by union-find.
  UnionFind pieces(static_cast<int>(n));
  std::map<std::pair<std::size_t, std::size_t>, idx_t> edge_owner;
  for (idx_t e = 0; e < n; ++e)
    for (int c = 0; c < 3; ++c) {
      const std::size_t a = triangles[e][c], b = triangles[e][(c + 1) % 3];
      const auto key = std::minmax(a, b);
      const auto [it, fresh] = edge_owner.emplace(key, e);
      if (!fresh && part[it->second] == part[e]) pieces.join(static_cast<int>(e), static_cast<int>(it->second));
    }
  std::vector<int> subdomain(n, -1);
  std::map<idx_t, int> number;
  for (idx_t e = 0; e < n; ++e) {
    const idx_t root = pieces.find(static_cast<int>(e));
    const auto [it, fresh] = number.emplace(root, static_cast<int>(number.size()));
    subdomain[e] = it->second;
  }
  return {subdomain, static_cast<int>(number.size())};
}

// Boundary edges of the rectangle from the triangles' own (counter-clockwise) edges, each side
// ordered counter-clockwise around the block.
void add_boundary_edges(mesh::Mesh& mesh, double eps) {
  const int width = mesh.triangles.width();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto tri = mesh.triangles[t];
    for (int c = 0; c < 3; ++c) {
      const int a = tri[c], b = tri[(c + 1) % 3], mid = width == 6 ? tri[3 + c] : -1;
      const int side = mesh::side_of(mesh, mesh.nodes[a], mesh.nodes[b], eps);
      if (side >= 0) mesh.boundary_edges[side].push_back({a, b, mid});
    }
  }
  // Counter-clockwise: bottom by x up, right by y up, top by x down, left by y down.
  const auto along = [&](int side, const mesh::Edge& e) {
    const Eigen::Vector2d& p = mesh.nodes[e.a];
    return side == mesh::bottom ? p.x() : side == mesh::right ? p.y() : side == mesh::top ? -p.x() : -p.y();
  };
  for (int side = 0; side < 4; ++side)
    std::sort(mesh.boundary_edges[side].begin(), mesh.boundary_edges[side].end(),
              [&](const mesh::Edge& x, const mesh::Edge& y) { return along(side, x) < along(side, y); });
}

// The physical points of the nodes, gmsh node tag by tag (tag_of: per node): the matrix's copies
// of a tag are one point, a fibre piece's copy another (joined by an interface pair, or on the
// right or top side by its partner's); the sides from the tag's position. Periodic pairs: gmsh
// meshed the right (top) curves as copies of the left (bottom) ones, so the two sides hold the
// same places in the same order along them, the matrix's point before the fibre's at each;
// point_problem checks that every partner is at its place.
void add_points(mesh::Mesh& mesh, const std::vector<std::size_t>& tag_of, double eps) {
  std::unordered_map<std::size_t, int> matrix_point;
  for (const mesh::Subdomain& sub : mesh.subdomains)
    for (int v = sub.node_begin; v < sub.node_end; ++v) {
      const auto [it, fresh] = matrix_point.emplace(tag_of[v], mesh.n_points());
      if (fresh || sub.is_fibre) mesh.point_sides.push_back(mesh::sides_at(mesh, mesh.nodes[v], eps));
      mesh.point_of.push_back(sub.is_fibre ? mesh.n_points() - 1 : it->second);
      if (fresh && sub.is_fibre) matrix_point.erase(it);
    }
  for (const auto& [side, opposite] : {std::pair{mesh::right, mesh::left}, std::pair{mesh::top, mesh::bottom}}) {
    const std::vector<int> copies = mesh::side_points(mesh, side), places = mesh::side_points(mesh, opposite);
    for (std::size_t i = 0; i < std::min(copies.size(), places.size()); ++i)
      mesh.periodic_pairs.push_back({copies[i], places[i], side});
  }
  if (const std::string problem = mesh::point_problem(mesh); !problem.empty())
    throw InputError("the periodic mesh does not match: " + problem);
}

// Interface pairs, fibre piece by fibre piece along its rim (by angle about its centre), and
// glue pairs where matrix subdomains meet, from the copies of every gmsh node tag: (subdomain,
// node), the matrix's n_matrix subdomains first.
void add_pairs(mesh::Mesh& mesh, const std::map<std::size_t, std::vector<std::pair<int, int>>>& copies, int n_matrix,
               double eps) {
  std::vector<std::vector<std::pair<double, std::array<int, 2>>>> rim(mesh.fibre_centres.size());
  for (const auto& [tag, c] : copies) {
    std::vector<int> in_matrix;
    for (const auto& [s, v] : c)
      if (s < n_matrix) in_matrix.push_back(v);
    for (std::size_t k = 1; k < in_matrix.size(); ++k) mesh.glue_pairs.push_back({in_matrix[0], in_matrix[k]});
    if (in_matrix.empty()) continue;
    // A rim point on the right or top side is the periodic copy of one on the left or bottom:
    // one physical point, one pair (two would be the same row twice; interface_edges gives
    // the copy's rim length to the pair it shares).
    const Eigen::Vector2d& at = mesh.nodes[c.front().second];
    if (std::abs(at.x() - mesh.block_width()) < eps || std::abs(at.y() - mesh.block_height()) < eps) continue;
    for (const auto& [s, v] : c)
      if (s >= n_matrix) {
        const int piece = s - n_matrix;
        const Eigen::Vector2d d = mesh.nodes[v] - mesh.fibre_centres[piece];
        rim[piece].push_back({std::atan2(d.y(), d.x()), {v, in_matrix[0]}});
      }
  }
  for (std::size_t piece = 0; piece < rim.size(); ++piece) {
    std::sort(rim[piece].begin(), rim[piece].end());
    for (const auto& [angle, pair] : rim[piece]) {
      mesh.interface_pairs.push_back(pair);
      mesh.interface_fibre.push_back(static_cast<int>(piece));
    }
  }
}

// gmsh's mesh of the unit cell (images: its fibre pieces there), split into subdomains and turned
// into the solver's mesh, back in the cell's units (× unit).
mesh::Mesh collect_mesh(const Geometry& geometry, const Microstructure& m, const std::vector<Image>& images,
                        const gmsh_model::Result& meshed, int subdomain_dofs, double unit, MeshReport& report) {
  const int width = geometry.element == Element::p1 ? 3 : 6;
  const auto row_size = static_cast<std::size_t>(width);
  std::unordered_map<std::size_t, Eigen::Vector2d> position;
  for (std::size_t i = 0; i < meshed.node_tags.size(); ++i)
    position[meshed.node_tags[i]] = {unit * meshed.xyz[3 * i], unit * meshed.xyz[3 * i + 1]};

  // Subdomains: the matrix's parts, then one per fibre piece (in the order of their images).
  std::vector<std::vector<std::size_t>> matrix;
  std::vector<std::pair<int, std::vector<std::vector<std::size_t>>>> fibres;  // (image, triangles)
  for (const gmsh_model::Surface& s : meshed.surfaces) {
    std::vector<std::vector<std::size_t>> rows;
    for (std::size_t e = 0; e + row_size <= s.triangles.size(); e += row_size)
      rows.emplace_back(s.triangles.begin() + e, s.triangles.begin() + e + row_size);
    if (s.image < 0)
      matrix.insert(matrix.end(), rows.begin(), rows.end());
    else
      fibres.push_back({s.image, std::move(rows)});
  }
  std::sort(fibres.begin(), fibres.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::set<std::size_t> matrix_nodes;
  for (const auto& t : matrix) matrix_nodes.insert(t.begin(), t.end());
  const Clock::time_point split_start = Clock::now();
  const int n_parts =
      subdomain_dofs == 0 ? 1 : std::max(1, static_cast<int>(std::lround(2.0 * matrix_nodes.size() / subdomain_dofs)));
  const auto [part, n_matrix] = split_matrix(matrix, n_parts);
  report.seconds_split = seconds_since(split_start);

  std::vector<std::vector<const std::vector<std::size_t>*>> rows_of(n_matrix + fibres.size());
  for (std::size_t e = 0; e < matrix.size(); ++e) rows_of[part[e]].push_back(&matrix[e]);
  for (std::size_t f = 0; f < fibres.size(); ++f)
    for (const auto& t : fibres[f].second) rows_of[n_matrix + f].push_back(&t);

  mesh::Mesh mesh;
  mesh.geometry = geometry;
  mesh.triangles = mesh::Triangles(width);
  // Every subdomain its own copy of its nodes; copies[tag]: (subdomain, node) of each.
  std::map<std::size_t, std::vector<std::pair<int, int>>> copies;
  std::vector<std::size_t> tag_of;  // per node
  for (int s = 0; s < static_cast<int>(rows_of.size()); ++s) {
    mesh::Subdomain sub;
    sub.is_fibre = s >= n_matrix;
    sub.fibre = sub.is_fibre ? s - n_matrix : -1;
    sub.node_begin = mesh.n_nodes();
    sub.triangle_begin = static_cast<int>(mesh.triangles.size());
    std::unordered_map<std::size_t, int> local;
    const auto node = [&](std::size_t tag) {
      const auto [it, fresh] = local.emplace(tag, mesh.n_nodes());
      if (fresh) {
        mesh.nodes.push_back(position.at(tag));
        tag_of.push_back(tag);
        copies[tag].push_back({s, it->second});
      }
      return it->second;
    };
    for (const auto* row : rows_of[s]) {
      std::vector<int> t(width);
      for (int i = 0; i < width; ++i) t[i] = node((*row)[i]);
      const Eigen::Vector2d a = mesh.nodes[t[1]] - mesh.nodes[t[0]], b = mesh.nodes[t[2]] - mesh.nodes[t[0]];
      if (a.x() * b.y() - a.y() * b.x() < 0) {  // clockwise: reverse, and the mid-sides with it
        std::swap(t[1], t[2]);
        if (width == 6) std::swap(t[3], t[5]);
      }
      mesh.triangles.push_back(std::span<const int>(t));
      mesh.triangle_subdomain.push_back(s);
    }
    sub.node_end = mesh.n_nodes();
    sub.triangle_end = static_cast<int>(mesh.triangles.size());
    mesh.subdomains.push_back(sub);
  }
  for (const auto& [image, rows] : fibres) {
    mesh.fibre_centres.push_back(unit * images[image].centre);
    mesh.fibre_radii.push_back(unit * images[image].radius);
  }
  const double eps = node_reach(std::max(m.Lx, m.Ly));
  add_pairs(mesh, copies, n_matrix, eps);
  add_boundary_edges(mesh, eps);
  add_points(mesh, tag_of, eps);
  report.fibre_pieces = static_cast<int>(fibres.size());
  report.matrix_parts = n_matrix;
  return mesh;
}

}  // namespace

mesh::Mesh build_rve_mesh(const Geometry& geometry, int subdomain_dofs, const std::string& where, MeshReport* report) {
  MeshReport local;
  MeshReport& r = report ? *report : local;
  const Microstructure m = microstructure_of(geometry, where);
  r.fibres = statistics(m);
  double r_mean = 0;
  for (const Fibre& f : m.fibres) r_mean += f.radius / m.fibres.size();
  const double h = rve_element_size(r_mean, geometry.degree);
  r.element_size = h;
  // The size field stops refining at the smallest element: a narrower gap would get elements of
  // angles near 0 (and a gap of 0 none at all).
  const double narrowest = std::min(r.fibres.gap_min, r.fibres.edge_gap_min);
  if (narrowest < h / rve_narrowest_gap_divisor)
    throw InputError(where + ": the narrowest gap (between fibres, to an edge, or a sliver of a fibre an edge cuts), " +
                     formatted("%.3g", narrowest) + ", is too narrow to mesh at degree " +
                     std::to_string(geometry.degree) + " (elements of h = " + formatted("%.3g", h) +
                     ", at least h/50 needed): raise min_gap or the degree");
  // A fibre far smaller than the smallest element is not resolved, and gmsh's OpenCASCADE
  // projections fail on it inside a parallel region, where no error can be caught.
  for (std::size_t i = 0; i < m.fibres.size(); ++i)
    if (m.fibres[i].radius < h / smallest_element_divisor)
      throw InputError(
          where + ": fibre " + std::to_string(i + 1) + " has radius " + formatted("%.3g", m.fibres[i].radius) +
          ", below h/10 = " + formatted("%.3g", h / smallest_element_divisor) + ", the smallest element at degree " +
          std::to_string(geometry.degree) + " (h = pi x mean radius / (4 degree)): raise the degree or leave it out");
  // The mesh budget from the fibres as placed (random radii are scaled to the volume fraction,
  // so the scene's mean radius, which the scene's own check used, may not be theirs).
  const double nodes = rve_node_estimate(m.Lx, m.Ly, r_mean, geometry.degree, geometry.element);
  if (nodes > max_mesh_nodes)
    throw InputError(where + ": the mesh would have about " + std::to_string(std::llround(nodes)) +
                     " nodes (element size pi r / (4 degree) = " + formatted("%.3g", h) +
                     " for the fibres' mean radius " + formatted("%.3g", r_mean) + "), more than the limit " +
                     std::to_string(max_mesh_nodes));
  // gmsh meshes the cell scaled by a power of two (exact) to a size in [1, 2): OpenCASCADE's
  // tolerances are absolute (1e-7), so a cell of size 1e-5 (metres) or 1e-300 would otherwise
  // fail inside it, and one of 1e300 lose every digit. Nodes come back in the cell's units.
  const double unit = std::exp2(std::floor(std::log2(std::max(m.Lx, m.Ly))));
  Microstructure unit_cell = m;
  unit_cell.Lx /= unit, unit_cell.Ly /= unit;
  for (Fibre& f : unit_cell.fibres) f.centre /= unit, f.radius /= unit;
  const std::vector<Image> images = images_in(unit_cell);
  gmsh_model::Request request;
  request.Lx = unit_cell.Lx, request.Ly = unit_cell.Ly;
  for (const Image& im : images) request.images.push_back({im.centre.x(), im.centre.y(), im.radius});
  request.size_max = h / unit;
  request.size_min = h / unit / smallest_element_divisor;
  const SizeField size(unit_cell, h / unit);
  request.size = [&size](double x, double y) { return size(x, y); };
  request.p2 = geometry.element == Element::p2;
  const Clock::time_point start = Clock::now();
  const gmsh_model::Result meshed = gmsh_model::mesh(request);
  if (!meshed.error.empty()) throw InputError(where + ": the RVE mesher: " + meshed.error);
  r.seconds_gmsh = seconds_since(start);
  try {
    return collect_mesh(geometry, m, images, meshed, subdomain_dofs, unit, r);
  } catch (const InputError& e) {
    throw InputError(where + ": the RVE mesher: " + e.what());
  }
}

}  // namespace dualcell::rve
