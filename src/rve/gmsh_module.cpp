// libdualcell-gmsh.so: the gmsh half of the RVE mesher (rve/gmsh_model.hpp), the only code of the
// project that calls gmsh. Built as a module and loaded by rve::gmsh_model::mesh.
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "rve/gmsh_model.hpp"

namespace dualcell::rve::gmsh_model {

namespace {

// gmsh's global state for one mesh: initialised quietly, finalised on every way out.
struct GmshSession {
  GmshSession() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::model::add("rve");
  }
  ~GmshSession() { gmsh::finalize(); }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

// A geometry this mesher cannot make periodic: the request's fault, not gmsh's.
struct GeometryError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Builds the OpenCASCADE geometry, fragments it and keeps what lies in the rectangle; the
// right and top curves are made periodic copies of the left and bottom ones. Returns the
// surfaces' (tag, image).
std::vector<std::pair<int, int>> build_geometry(const Request& r) {
  namespace occ = gmsh::model::occ;
  const int rectangle = occ::addRectangle(0, 0, 0, r.Lx, r.Ly);
  gmsh::vectorpair disks;
  for (const Disk& d : r.images) disks.push_back({2, occ::addDisk(d.x, d.y, 0, d.radius, d.radius)});
  gmsh::vectorpair pieces;
  std::vector<gmsh::vectorpair> children;
  occ::fragment({{2, rectangle}}, disks, pieces, children);
  // No synchronize before the outside pieces are removed: gmsh 4.8 does not free the model
  // entities that a later synchronize drops (AddressSanitizer reports them as leaks).
  // children[0]: the pieces of the rectangle; children[1 + j]: those of disk j. A piece of both
  // is the part of image j inside the rectangle.
  std::set<int> inside;
  for (const auto& [dim, tag] : children[0]) inside.insert(tag);
  std::map<int, int> image_of;
  for (std::size_t j = 0; j < r.images.size(); ++j)
    for (const auto& [dim, tag] : children[1 + j])
      if (inside.count(tag)) image_of[tag] = static_cast<int>(j);
  gmsh::vectorpair outside;
  for (const auto& [dim, tag] : pieces)
    if (!inside.count(tag)) outside.push_back({dim, tag});
  if (!outside.empty()) occ::remove(outside, true);
  occ::synchronize();
  std::vector<std::pair<int, int>> surfaces;
  for (int tag : inside) surfaces.push_back({tag, image_of.count(tag) ? image_of[tag] : -1});

  // Periodic edges: every curve on the right (top) side is the copy of the curve on the left
  // (bottom) side at the same place, matched by their bounding boxes.
  const double L = std::max(r.Lx, r.Ly), eps = 1e-7 * L;
  const auto curves_on = [&](double x0, double y0, double x1, double y1) {
    gmsh::vectorpair c;
    gmsh::model::getEntitiesInBoundingBox(x0 - eps, y0 - eps, -eps, x1 + eps, y1 + eps, eps, c, 1);
    return c;
  };
  const auto box = [](int tag) {
    std::array<double, 6> b{};
    gmsh::model::getBoundingBox(1, tag, b[0], b[1], b[2], b[3], b[4], b[5]);
    return b;
  };
  const auto match = [&](const gmsh::vectorpair& from, const gmsh::vectorpair& to, double dx, double dy) {
    for (const auto& [d, t] : to) {
      const auto bt = box(t);
      int master = -1;
      for (const auto& [e, s] : from) {
        const auto bs = box(s);
        if (std::abs(bs[0] + dx - bt[0]) < 10 * eps && std::abs(bs[1] + dy - bt[1]) < 10 * eps &&
            std::abs(bs[3] + dx - bt[3]) < 10 * eps && std::abs(bs[4] + dy - bt[4]) < 10 * eps)
          master = s;
      }
      if (master < 0) throw GeometryError("an edge curve has no periodic partner on the opposite side");
      gmsh::model::mesh::setPeriodic(1, {t}, {master}, {1, 0, 0, dx, 0, 1, 0, dy, 0, 0, 1, 0, 0, 0, 0, 1});
    }
  };
  match(curves_on(0, 0, 0, r.Ly), curves_on(r.Lx, 0, r.Lx, r.Ly), r.Lx, 0);
  match(curves_on(0, 0, r.Lx, 0), curves_on(0, r.Ly, r.Lx, r.Ly), 0, r.Ly);
  return surfaces;
}

void mesh_request(const Request& r, Result& out) {
  const auto surfaces = build_geometry(r);
  gmsh::option::setNumber("Mesh.Algorithm", 6);  // Frontal-Delaunay
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeMax", r.size_max);
  gmsh::option::setNumber("Mesh.MeshSizeMin", r.size_min);
  gmsh::model::mesh::setSizeCallback([&r](int, int, double x, double y, double) { return r.size(x, y); });
  gmsh::model::mesh::generate(2);
  if (r.p2) gmsh::model::mesh::setOrder(2);
  std::vector<double> parametric;
  gmsh::model::mesh::getNodes(out.node_tags, out.xyz, parametric, -1, -1, false, false);
  for (const auto& [tag, image] : surfaces) {
    Surface s;
    s.image = image;
    std::vector<std::size_t> element_tags;
    gmsh::model::mesh::getElementsByType(r.p2 ? 9 : 2, element_tags, s.triangles, tag);
    out.surfaces.push_back(std::move(s));
  }
}

}  // namespace

}  // namespace dualcell::rve::gmsh_model

// The entry point: every exception stays inside (gmsh reports an error by one of its own, its
// last logged error is the message).
extern "C" __attribute__((visibility("default"))) void dualcell_gmsh_mesh(
    const dualcell::rve::gmsh_model::Request& request, dualcell::rve::gmsh_model::Result& result) {
  namespace model = dualcell::rve::gmsh_model;
  result = {};
  try {
    model::GmshSession session;
    try {
      model::mesh_request(request, result);
    } catch (const model::GeometryError& e) {
      result = {};
      result.error = e.what();
    } catch (...) {
      std::string message;
      gmsh::logger::getLastError(message);
      result = {};
      result.error = "gmsh failed: " + (message.empty() ? std::string("no message") : message);
    }
  } catch (...) {
    result = {};
    result.error = "gmsh failed to start or to finish";
  }
}
