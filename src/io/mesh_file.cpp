#include "io/mesh_file.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"
#include "io/atomic_output.hpp"
#include "io/file_root.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace dualcell::io {

namespace {

template <std::size_t N>
std::vector<std::int64_t> flatten(const std::vector<std::array<int, N>>& rows) {
  std::vector<std::int64_t> flat;
  flat.reserve(rows.size() * N);
  for (const auto& row : rows)
    for (int v : row) flat.push_back(v);
  return flat;
}

std::vector<std::int64_t> flatten(const mesh::Triangles& triangles) {
  return {triangles.flat().begin(), triangles.flat().end()};
}

// Boundary edges as rows (a, b) for p1 or (a, b, mid) for p2.
std::vector<std::int64_t> flatten(const std::vector<mesh::Edge>& edges, int width) {
  std::vector<std::int64_t> flat;
  for (const auto& e : edges) {
    flat.insert(flat.end(), {e.a, e.b});
    if (width == 3) flat.push_back(e.mid);
  }
  return flat;
}

std::vector<double> flatten(const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> flat;
  flat.reserve(points.size() * 2);
  for (const auto& p : points) {
    flat.push_back(p.x());
    flat.push_back(p.y());
  }
  return flat;
}

// Rows of N node (or range) indices, each in [0, max_index).
std::vector<int> indices_of(const File& f, const std::string& name, std::int64_t max_index, hsize_t n_rows,
                            hsize_t width) {
  const auto flat = f.read_ints(name, {n_rows, width});
  std::vector<int> out(flat.size());
  for (std::size_t i = 0; i < flat.size(); ++i) {
    if (flat[i] < 0 || flat[i] >= max_index)
      throw InputError(f.path().string() + ": " + name + ": node index " + std::to_string(flat[i]) +
                       " out of range [0, " + std::to_string(max_index) + ")");
    out[i] = static_cast<int>(flat[i]);
  }
  return out;
}

template <std::size_t N>
std::vector<std::array<int, N>> rows_of(const File& f, const std::string& name, std::int64_t max_index,
                                        hsize_t n_rows = any_extent) {
  const auto flat = indices_of(f, name, max_index, n_rows, N);
  std::vector<std::array<int, N>> rows(flat.size() / N);
  for (std::size_t i = 0; i < flat.size(); ++i) rows[i / N][i % N] = flat[i];
  return rows;
}

// An RVE's geometry as written in its scene: size, min_gap, the random spec (attributes of
// /mesh) or the list (/mesh/rve_fibres, K×3: x, y, r).
void write_rve_geometry(File& f, const Geometry& g) {
  f.write_attribute("/mesh", "size", std::vector<double>{g.size[0], g.size[1]});
  f.write_attribute("/mesh", "min_gap", g.random.min_gap);
  if (g.layout == FibreLayout::random) {
    f.write_attribute("/mesh", "volume_fraction", g.random.volume_fraction);
    f.write_attribute("/mesh", "radius", std::vector<double>{g.random.radius_mean, g.random.radius_sd});
    f.write_attribute("/mesh", "seed", static_cast<std::int64_t>(g.random.seed));
    return;
  }
  std::vector<double> list;
  for (const FibreCircle& c : g.fibres) list.insert(list.end(), {c.centre[0], c.centre[1], c.radius});
  f.write("/mesh/rve_fibres", list, {g.fibres.size(), 3});
}

void read_rve_geometry(const File& f, Geometry& g, const std::string& where) {
  const std::string layout = f.read_string_attribute("/mesh", "layout");
  if (layout == "cells") return;
  if (layout != "list" && layout != "random")
    throw InputError(where + "/mesh attribute layout = \"" + clipped(layout) +
                     "\": allowed \"cells\", \"list\" or \"random\"");
  g.layout = layout == "list" ? FibreLayout::list : FibreLayout::random;
  const auto size = f.read_double_attribute("/mesh", "size", 2);
  g.size = {size[0], size[1]};
  if (!(g.size[0] > 0 && g.size[1] > 0 && std::isfinite(g.size[0]) && std::isfinite(g.size[1])))
    throw InputError(where + "/mesh attribute size: must be 2 finite numbers > 0");
  g.random.min_gap = f.read_double_attribute_value("/mesh", "min_gap");
  if (g.layout == FibreLayout::random) {
    g.random.volume_fraction = f.read_double_attribute_value("/mesh", "volume_fraction");
    const auto radius = f.read_double_attribute("/mesh", "radius", 2);
    g.random.radius_mean = radius[0];
    g.random.radius_sd = radius[1];
    g.random.seed = static_cast<std::uint64_t>(f.read_int_attribute_value("/mesh", "seed"));
    return;
  }
  const auto list = f.read_doubles("/mesh/rve_fibres", {any_extent, 3});
  for (std::size_t k = 0; k < list.size() / 3; ++k)
    g.fibres.push_back({{list[3 * k], list[3 * k + 1]}, list[3 * k + 2]});
}

// What the solver relies on, so that a corrupt or edited file is refused instead of indexing out
// of bounds or silently solving another problem: one fibre and one matrix subdomain per cell;
// every triangle counter-clockwise, not degenerate, with its nodes in its own subdomain; nodes in
// the block; interface pairs joining the fibre and the matrix of their cell at one point; glue
// pairs and boundary edges on matrix nodes.
void check_structure(const mesh::Mesh& m, const std::vector<std::int64_t>& is_fibre, const std::string& where) {
  const Geometry& g = m.geometry;
  const bool rve = g.rve();
  if (!rve &&
      (!(g.cell_size > 0 && std::isfinite(g.cell_size)) || !(g.fibre_radius > 0 && std::isfinite(g.fibre_radius)) ||
       g.cells[0] < 1 || g.cells[1] < 1 || g.degree < 1))
    throw InputError(where + "/mesh: attributes cells, cell_size, fibre_radius or degree out of range");
  // A cell's fibre and matrix subdomains (mapped), or an RVE's fibre pieces (matrix: cell −1).
  const auto cells = static_cast<std::size_t>(rve ? m.n_fibres() : m.n_cells());
  std::vector<int> fibre_of(cells, -1), matrix_of(cells, -1);
  for (std::size_t s = 0; s < m.subdomains.size(); ++s) {
    const int c = rve ? m.subdomains[s].fibre : m.subdomains[s].cell;
    const bool rve_matrix = rve && is_fibre[s] == 0;
    if ((rve_matrix ? c != -1 : (c < 0 || static_cast<std::size_t>(c) >= cells)) ||
        (is_fibre[s] != 0 && is_fibre[s] != 1))
      throw InputError(where + "/mesh/subdomain_cell or subdomain_is_fibre: subdomain " + std::to_string(s) +
                       " has cell " + std::to_string(c) + " and flag " + std::to_string(is_fibre[s]));
    if (rve_matrix) continue;
    int& slot = is_fibre[s] ? fibre_of[c] : matrix_of[c];
    if (slot >= 0)
      throw InputError(where + "/mesh/subdomain_is_fibre: cell " + std::to_string(c) + " has two " +
                       (is_fibre[s] ? "fibre" : "matrix") + " subdomains");
    slot = static_cast<int>(s);
  }
  for (double r : m.fibre_radii)
    if (!(r > 0 && std::isfinite(r)))
      throw InputError(where + "/mesh/fibre_radii: a radius is not a finite number > 0");
  std::vector<int> owner(m.nodes.size());
  for (std::size_t s = 0; s < m.subdomains.size(); ++s)
    for (int v = m.subdomains[s].node_begin; v < m.subdomains[s].node_end; ++v) owner[v] = static_cast<int>(s);
  const double tol = mesh::side_tolerance(m);
  for (std::size_t v = 0; v < m.nodes.size(); ++v)
    if (m.nodes[v].x() < -tol || m.nodes[v].x() > m.block_width() + tol || m.nodes[v].y() < -tol ||
        m.nodes[v].y() > m.block_height() + tol)
      throw InputError(where + "/mesh/nodes: node " + std::to_string(v) + " lies outside the block of cells");
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto tri = m.triangles[t];
    const int s = m.triangle_subdomain[t];
    if (std::any_of(tri.begin(), tri.end(), [&](int v) { return owner[v] != s; }) ||
        static_cast<int>(t) < m.subdomains[s].triangle_begin || static_cast<int>(t) >= m.subdomains[s].triangle_end)
      throw InputError(where + "/mesh/triangles: triangle " + std::to_string(t) + " is not inside its subdomain " +
                       std::to_string(s));
    const Eigen::Vector2d a = m.nodes[tri[1]] - m.nodes[tri[0]], b = m.nodes[tri[2]] - m.nodes[tri[0]];
    if (!(a.x() * b.y() - a.y() * b.x() > 0))
      throw InputError(where + "/mesh/triangles: triangle " + std::to_string(t) + " is degenerate or clockwise");
  }
  for (const auto& centre : m.fibre_centres)
    if (!centre.allFinite()) throw InputError(where + "/mesh/fibre_centres: non-finite centre");
  const auto coincide = [&](int u, int v) { return (m.nodes[u] - m.nodes[v]).norm() <= tol; };
  for (std::size_t p = 0; p < m.interface_pairs.size(); ++p) {
    const auto [f, mn] = m.interface_pairs[p];
    const int c = m.interface_fibre[p];
    if (owner[f] != fibre_of[c] || is_fibre[owner[mn]] || (!rve && owner[mn] != matrix_of[c]) || !coincide(f, mn))
      throw InputError(where + "/mesh/interface_pairs: pair " + std::to_string(p) +
                       " does not join coinciding fibre and matrix nodes of cell " + std::to_string(c));
  }
  for (std::size_t q = 0; q < m.glue_pairs.size(); ++q) {
    const auto [u, v] = m.glue_pairs[q];
    if (is_fibre[owner[u]] || is_fibre[owner[v]] || owner[u] == owner[v] || !coincide(u, v))
      throw InputError(where + "/mesh/glue_pairs: pair " + std::to_string(q) +
                       " does not join coinciding matrix nodes of two cells");
  }
  for (int side = 0; side < 4; ++side) {
    // left, right, bottom, top: the coordinate (x or y) and its value on that side
    const int axis = side / 2;
    const double at = side == 1 ? m.block_width() : side == 3 ? m.block_height() : 0.0;
    for (const auto& [u, v, mid] : m.boundary_edges[side])
      if ((!rve && is_fibre[owner[u]]) || owner[u] != owner[v] || u == v || std::abs(m.nodes[u][axis] - at) > tol ||
          std::abs(m.nodes[v][axis] - at) > tol ||
          (mid >= 0 && (owner[mid] != owner[u] || (m.nodes[mid] - (m.nodes[u] + m.nodes[v]) / 2).norm() > tol)))
        throw InputError(where + "/mesh/boundary/" + mesh::side_names[side] +
                         ": an edge that is not a matrix edge (or an RVE's edge) on that side of the block");
  }
}

// The physical points (mesh::Mesh::point_of, point_sides, periodic_pairs as rows point,
// partner, side).
void write_points(File& f, const mesh::Mesh& mesh) {
  f.write("/mesh/point_of", std::vector<std::int64_t>(mesh.point_of.begin(), mesh.point_of.end()),
          {mesh.point_of.size()});
  f.write("/mesh/point_sides", std::vector<std::int64_t>(mesh.point_sides.begin(), mesh.point_sides.end()),
          {mesh.point_sides.size()});
  std::vector<std::int64_t> pairs;
  for (const auto& [point, partner, side] : mesh.periodic_pairs) pairs.insert(pairs.end(), {point, partner, side});
  f.write("/mesh/periodic_pairs", pairs, {mesh.periodic_pairs.size(), 3});
}

// The physical points: the point indices in range here, what they say by mesh::point_problem.
void read_points(const File& f, mesh::Mesh& m, const std::string& where) {
  const auto sides = f.read_ints("/mesh/point_sides", {any_extent});
  const auto n_points = static_cast<std::int64_t>(sides.size());
  const auto point = [&](std::int64_t p, const char* name) {
    if (p < 0 || p >= n_points)
      throw InputError(where + "/mesh/" + name + ": point " + std::to_string(p) + " out of range [0, " +
                       std::to_string(n_points) + ")");
    return static_cast<int>(p);
  };
  for (std::int64_t s : sides) {
    if (s < 0 || s > 15)
      throw InputError(where + "/mesh/point_sides: " + std::to_string(s) + " is not a set of sides (0 to 15)");
    m.point_sides.push_back(static_cast<std::uint8_t>(s));
  }
  for (std::int64_t p : f.read_ints("/mesh/point_of", {m.nodes.size()}, " like /mesh/nodes"))
    m.point_of.push_back(point(p, "point_of"));
  const auto pairs = f.read_ints("/mesh/periodic_pairs", {any_extent, 3});
  for (std::size_t i = 0; i < pairs.size(); i += 3) {
    if (pairs[i + 2] != mesh::right && pairs[i + 2] != mesh::top)
      throw InputError(where + "/mesh/periodic_pairs: pair " + std::to_string(i / 3) + " has side " +
                       std::to_string(pairs[i + 2]) + ", not 1 (right) or 3 (top)");
    m.periodic_pairs.push_back({point(pairs[i], "periodic_pairs"), point(pairs[i + 1], "periodic_pairs"),
                                static_cast<mesh::Side>(pairs[i + 2])});
  }
  if (const std::string problem = mesh::point_problem(m); !problem.empty())
    throw InputError(where + "/mesh/" + problem);
}

}  // namespace

void write_mesh(const mesh::Mesh& mesh, const Scene& scene, const std::filesystem::path& h5) {
  const std::filesystem::path xdmf = xdmf_beside(h5);
  AtomicOutputs outputs;
  outputs.add(h5);
  outputs.add(xdmf);
  {
    File f = File::create(h5);
    const hsize_t N = mesh.nodes.size(), T = mesh.triangles.size(), S = mesh.subdomains.size();
    f.create_group("/mesh");
    f.write("/mesh/nodes", flatten(mesh.nodes), {N, 2});
    const hsize_t W = mesh.triangles.width(), E = W == 6 ? 3 : 2;  // nodes per triangle and per edge
    f.write("/mesh/triangles", flatten(mesh.triangles), {T, W});
    std::vector<std::int64_t> tri_sub(mesh.triangle_subdomain.begin(), mesh.triangle_subdomain.end());
    std::vector<std::int64_t> tri_fibre(T);
    for (std::size_t t = 0; t < T; ++t) tri_fibre[t] = mesh.subdomains[mesh.triangle_subdomain[t]].is_fibre;
    f.write("/mesh/triangle_subdomain", tri_sub, {T});
    f.write("/mesh/triangle_is_fibre", tri_fibre, {T});
    std::vector<std::int64_t> is_fibre, cell, node_range, triangle_range;
    for (const auto& s : mesh.subdomains) {
      is_fibre.push_back(s.is_fibre);
      cell.push_back(mesh.geometry.rve() ? s.fibre : s.cell);  // the format's subdomain_cell
      node_range.insert(node_range.end(), {s.node_begin, s.node_end});
      triangle_range.insert(triangle_range.end(), {s.triangle_begin, s.triangle_end});
    }
    f.write("/mesh/subdomain_is_fibre", is_fibre, {S});
    f.write("/mesh/subdomain_cell", cell, {S});
    f.write("/mesh/subdomain_nodes", node_range, {S, 2});
    f.write("/mesh/subdomain_triangles", triangle_range, {S, 2});
    f.write("/mesh/fibre_centres", flatten(mesh.fibre_centres), {mesh.fibre_centres.size(), 2});
    f.write("/mesh/fibre_radii", mesh.fibre_radii, {mesh.fibre_radii.size()});
    f.write("/mesh/interface_pairs", flatten(mesh.interface_pairs), {mesh.interface_pairs.size(), 2});
    f.write("/mesh/interface_cell", std::vector<std::int64_t>(mesh.interface_fibre.begin(), mesh.interface_fibre.end()),
            {mesh.interface_fibre.size()});
    f.write("/mesh/glue_pairs", flatten(mesh.glue_pairs), {mesh.glue_pairs.size(), 2});
    for (int side = 0; side < 4; ++side)
      f.write(std::string("/mesh/boundary/") + mesh::side_names[side], flatten(mesh.boundary_edges[side], E),
              {mesh.boundary_edges[side].size(), E});
    write_points(f, mesh);
    const Geometry& g = mesh.geometry;
    f.write_attribute("/mesh", "layout", std::string(to_string(g.layout)));
    if (g.rve()) write_rve_geometry(f, g);
    f.write_attribute("/mesh", "cells", std::vector<std::int64_t>{g.cells[0], g.cells[1]});
    f.write_attribute("/mesh", "cell_size", g.cell_size);
    f.write_attribute("/mesh", "fibre_radius", g.fibre_radius);
    f.write_attribute("/mesh", "fibre_offset", std::vector<double>{g.fibre_offset[0], g.fibre_offset[1]});
    f.write_attribute("/mesh", "degree", std::int64_t{g.degree});
    f.write_attribute("/mesh", "element", std::string(to_string(g.element)));
    Provenance provenance;
    provenance.scene_text = scene.text;
    provenance.scene_file = scene.file.string();
    provenance.material_text = scene.material_text;
    write_provenance(f, mesh_format, provenance);
    outputs.write(h5, f.close_to_image());
  }
  XdmfGrid grid;
  grid.nodes_dataset = "/mesh/nodes";
  grid.n_nodes = mesh.nodes.size();
  grid.triangles_dataset = "/mesh/triangles";
  grid.n_triangles = mesh.triangles.size();
  grid.nodes_per_triangle = mesh.triangles.width();
  grid.fields.push_back({"subdomain", "/mesh/triangle_subdomain", true, {grid.n_triangles}, true});
  grid.fields.push_back({"is_fibre", "/mesh/triangle_is_fibre", true, {grid.n_triangles}, true});
  outputs.write(xdmf, xdmf_text(h5.filename().string(), {grid}));
  outputs.commit();
}

MeshFile read_mesh(const std::filesystem::path& h5) {
  File f = File::open_read(h5);
  const std::string where = h5.string() + ": ";
  check_format(f, mesh_format);
  MeshFile out;
  mesh::Mesh& m = out.mesh;
  const auto cells = f.read_int_attribute("/mesh", "cells", 2);
  const auto offset = f.read_double_attribute("/mesh", "fibre_offset", 2);
  m.geometry.cells = {static_cast<int>(cells[0]), static_cast<int>(cells[1])};
  m.geometry.cell_size = f.read_double_attribute_value("/mesh", "cell_size");
  m.geometry.fibre_radius = f.read_double_attribute_value("/mesh", "fibre_radius");
  m.geometry.fibre_offset = {offset[0], offset[1]};
  m.geometry.degree = static_cast<int>(f.read_int_attribute_value("/mesh", "degree"));
  const std::string element = f.read_string_attribute("/mesh", "element");
  if (element != "p1" && element != "p2")
    throw InputError(where + "/mesh attribute element = \"" + clipped(element) + "\": allowed \"p1\" or \"p2\"");
  m.geometry.element = element == "p1" ? Element::p1 : Element::p2;
  read_rve_geometry(f, m.geometry, where);
  const int W = m.geometry.element == Element::p1 ? 3 : 6, E = W == 6 ? 3 : 2;  // nodes per triangle, per edge
  out.scene_text = f.read_string_attribute("/", "scene");

  const auto nodes = f.read_doubles("/mesh/nodes", {any_extent, 2});
  const std::int64_t N = static_cast<std::int64_t>(nodes.size() / 2);
  for (double x : nodes)
    if (!std::isfinite(x)) throw InputError(where + "/mesh/nodes: non-finite coordinate");
  m.nodes.resize(N);
  for (std::int64_t i = 0; i < N; ++i) m.nodes[i] = {nodes[2 * i], nodes[2 * i + 1]};
  m.triangles = mesh::Triangles(W);
  {
    const auto flat = indices_of(f, "/mesh/triangles", N, any_extent, W);
    for (std::size_t t = 0; t < flat.size() / W; ++t)
      m.triangles.push_back(std::span<const int>(flat.data() + t * W, W));
  }
  const std::size_t T = m.triangles.size();
  const auto tri_sub = f.read_ints("/mesh/triangle_subdomain", {T}, " like /mesh/triangles");
  const auto is_fibre = f.read_ints("/mesh/subdomain_is_fibre", {any_extent});
  const hsize_t S = is_fibre.size();
  const auto cell = f.read_ints("/mesh/subdomain_cell", {S}, " like /mesh/subdomain_is_fibre");
  const auto node_range = rows_of<2>(f, "/mesh/subdomain_nodes", N + 1, S);
  const auto tri_range = rows_of<2>(f, "/mesh/subdomain_triangles", static_cast<std::int64_t>(T) + 1, S);
  int next_node = 0, next_tri = 0;
  for (std::size_t s = 0; s < S; ++s) {
    // subdomain_cell holds the mapped block's cell (a fibre's row of fibre_centres is its cell),
    // or an RVE's fibre piece (−1 for the matrix).
    const int stored = static_cast<int>(cell[s]);
    mesh::Subdomain sub{is_fibre[s] != 0,
                        is_fibre[s] != 0 ? stored : -1,
                        m.geometry.rve() ? -1 : stored,
                        node_range[s][0],
                        node_range[s][1],
                        tri_range[s][0],
                        tri_range[s][1]};
    if (sub.node_begin != next_node || sub.node_end <= sub.node_begin || sub.triangle_begin != next_tri ||
        sub.triangle_end <= sub.triangle_begin)
      throw InputError(where + "/mesh/subdomain_nodes or subdomain_triangles: subdomain " + std::to_string(s) +
                       " ranges are not contiguous");
    next_node = sub.node_end;
    next_tri = sub.triangle_end;
    m.subdomains.push_back(sub);
  }
  if (next_node != N || next_tri != static_cast<int>(T))
    throw InputError(where + "subdomains do not cover all nodes and triangles");
  for (std::size_t t = 0; t < T; ++t) {
    if (tri_sub[t] < 0 || tri_sub[t] >= static_cast<std::int64_t>(S))
      throw InputError(where + "/mesh/triangle_subdomain: index out of range");
    m.triangle_subdomain.push_back(static_cast<int>(tri_sub[t]));
  }
  const auto centres = f.read_doubles("/mesh/fibre_centres", {any_extent, 2});
  for (std::size_t c = 0; c < centres.size() / 2; ++c) m.fibre_centres.emplace_back(centres[2 * c], centres[2 * c + 1]);
  m.fibre_radii = f.read_doubles("/mesh/fibre_radii", {m.fibre_centres.size()}, " like /mesh/fibre_centres");
  m.interface_pairs = rows_of<2>(f, "/mesh/interface_pairs", N);
  for (auto c : f.read_ints("/mesh/interface_cell", {m.interface_pairs.size()}, " like /mesh/interface_pairs")) {
    if (c < 0 || c >= static_cast<std::int64_t>(m.fibre_centres.size()))
      throw InputError(where + "/mesh/interface_cell: index out of range");
    m.interface_fibre.push_back(static_cast<int>(c));
  }
  m.glue_pairs = rows_of<2>(f, "/mesh/glue_pairs", N);
  for (int side = 0; side < 4; ++side) {
    const auto flat = indices_of(f, std::string("/mesh/boundary/") + mesh::side_names[side], N, any_extent, E);
    for (std::size_t e = 0; e < flat.size() / E; ++e)
      m.boundary_edges[side].push_back({flat[e * E], flat[e * E + 1], E == 3 ? flat[e * E + 2] : -1});
  }
  if (!m.geometry.rve() && (static_cast<int>(m.fibre_centres.size()) != m.n_cells() || S != 2 * m.fibre_centres.size()))
    throw InputError(where + "cell count does not match /mesh attribute cells");
  check_structure(m, is_fibre, where);
  read_points(f, m, where);
  return out;
}

std::string geometry_mismatch(const mesh::Mesh& mesh, const Scene& scene) {
  const Geometry& a = mesh.geometry;
  const Geometry& b = scene.geometry;
  std::ostringstream s;
  const auto pair_text = [](std::array<double, 2> v) {
    std::ostringstream t;
    t << '[' << shortest(v[0]) << ", " << shortest(v[1]) << ']';
    return t.str();
  };
  if (a.layout != b.layout) {
    s << "[geometry] the fibres: mesh " << to_string(a.layout) << ", scene " << to_string(b.layout);
    return s.str();
  }
  if (a.rve()) {
    const auto list = [](const Geometry& g) {
      std::vector<double> v;
      for (const FibreCircle& c : g.fibres) v.insert(v.end(), {c.centre[0], c.centre[1], c.radius});
      return v;
    };
    const RandomFibres &ra = a.random, &rb = b.random;
    if (a.size != b.size)
      s << "[geometry] size: mesh " << pair_text(a.size) << ", scene " << pair_text(b.size);
    else if (a.degree != b.degree)
      s << "[geometry] degree: mesh " << a.degree << ", scene " << b.degree;
    else if (a.element != b.element)
      s << "[geometry] element: mesh " << to_string(a.element) << ", scene " << to_string(b.element);
    else if (ra.min_gap != rb.min_gap)
      s << "[geometry] min_gap: mesh " << shortest(ra.min_gap) << ", scene " << shortest(rb.min_gap);
    else if (a.layout == FibreLayout::random &&
             (ra.volume_fraction != rb.volume_fraction || ra.radius_mean != rb.radius_mean ||
              ra.radius_sd != rb.radius_sd || ra.seed != rb.seed))
      s << "[geometry] volume_fraction, radius or seed: mesh " << shortest(ra.volume_fraction) << ", "
        << pair_text({ra.radius_mean, ra.radius_sd}) << ", " << ra.seed << "; scene " << shortest(rb.volume_fraction)
        << ", " << pair_text({rb.radius_mean, rb.radius_sd}) << ", " << rb.seed;
    else if (a.layout == FibreLayout::list && list(a) != list(b))
      s << "[[fibres]]: the mesh's " << a.fibres.size() << " fibres differ from the scene's " << b.fibres.size();
    return s.str();
  }
  if (a.cells != b.cells)
    s << "[geometry] cells: mesh [" << a.cells[0] << ", " << a.cells[1] << "], scene [" << b.cells[0] << ", "
      << b.cells[1] << "]";
  else if (a.degree != b.degree)
    s << "[geometry] degree: mesh " << a.degree << ", scene " << b.degree;
  else if (a.element != b.element)
    s << "[geometry] element: mesh " << to_string(a.element) << ", scene " << to_string(b.element);
  else if (a.cell_size != b.cell_size)
    s << "[geometry] cell_size: mesh " << shortest(a.cell_size) << ", scene " << shortest(b.cell_size);
  else if (a.fibre_radius != b.fibre_radius)
    s << "[geometry] fibre_radius: mesh " << shortest(a.fibre_radius) << ", scene " << shortest(b.fibre_radius);
  else if (a.fibre_offset != b.fibre_offset)
    s << "[geometry] fibre_offset: mesh [" << shortest(a.fibre_offset[0]) << ", " << shortest(a.fibre_offset[1])
      << "], scene [" << shortest(b.fibre_offset[0]) << ", " << shortest(b.fibre_offset[1]) << "]";
  return s.str();
}

}  // namespace dualcell::io
