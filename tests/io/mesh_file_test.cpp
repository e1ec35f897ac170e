// mesh.h5 round trip, its XDMF read by a real reader (meshio, Debian python3-meshio), and
// refusal of corrupt files.
#include "io/mesh_file.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.hpp"
#include "io/hdf5.hpp"
#include "test_util.hpp"

namespace dualcell::io {
namespace {

class MeshFileOrders : public ::testing::TestWithParam<Element> {};
INSTANTIATE_TEST_SUITE_P(Order, MeshFileOrders, ::testing::Values(Element::p1, Element::p2),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST_P(MeshFileOrders, RoundTripKeepsEverything) {
  testing::ScratchDir dir;
  const Scene scene = parse_scene(testing::scene_text(3, 2, 2, 0.3, "", to_string(GetParam())), dir / "s.toml");
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  write_mesh(m, scene, dir / "mesh.h5");
  EXPECT_TRUE(std::filesystem::exists(dir / "mesh.xdmf"));
  const MeshFile back = read_mesh(dir / "mesh.h5");
  EXPECT_EQ(back.mesh.nodes, m.nodes);
  EXPECT_EQ(back.mesh.triangles, m.triangles);
  EXPECT_EQ(back.mesh.interface_pairs, m.interface_pairs);
  EXPECT_EQ(back.mesh.glue_pairs, m.glue_pairs);
  EXPECT_EQ(back.mesh.boundary_edges, m.boundary_edges);
  EXPECT_EQ(back.mesh.point_of, m.point_of);
  EXPECT_EQ(back.mesh.point_sides, m.point_sides);
  EXPECT_EQ(back.mesh.periodic_pairs, m.periodic_pairs);
  EXPECT_EQ(back.mesh.subdomains.size(), m.subdomains.size());
  EXPECT_EQ(back.scene_text, scene.text);
  EXPECT_EQ(geometry_mismatch(back.mesh, scene), "");
  Scene other = scene;
  other.geometry.degree = 3;
  EXPECT_EQ(geometry_mismatch(back.mesh, other), "[geometry] degree: mesh 2, scene 3");
  other = scene;
  other.geometry.element = GetParam() == Element::p1 ? Element::p2 : Element::p1;
  EXPECT_EQ(geometry_mismatch(back.mesh, other), std::string("[geometry] element: mesh ") + to_string(GetParam()) +
                                                     ", scene " + to_string(other.geometry.element));
  // No temporaries left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 2);  // mesh.h5 and mesh.xdmf, no temporaries
}

// meshio reads p1 meshes as `triangle` and p2 as `triangle6` cells (XDMF Triangle_6), with the
// node order of /mesh/triangles: the first cell's nodes come back as written.
TEST_P(MeshFileOrders, XdmfOpensInMeshioWithSubdomainField) {
  testing::ScratchDir dir;
  const Scene scene = parse_scene(testing::scene_text(2, 2, 1, 0.3, "", to_string(GetParam())), dir / "s.toml");
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  write_mesh(m, scene, dir / "mesh.h5");
  // Debian's meshio lives in the system Python, not in any other python3 on PATH.
  const std::string script =
      "import meshio, sys\n"
      "m = meshio.read(sys.argv[1])\n"
      "tri = m.cells_dict['" +
      std::string(GetParam() == Element::p1 ? "triangle" : "triangle6") +
      "']\n"
      "assert tri.shape[1] == " +
      std::to_string(m.triangles.width()) +
      "\n"
      "first = [int(v) for v in tri[0]]\n"
      "sub = m.cell_data['subdomain'][0]\n"
      "print(len(m.points), len(tri), int(sub.max()) + 1, int(m.cell_data['is_fibre'][0].sum()), *first)\n";
  const auto py = dir.write("read.py", script);
  const auto r = testing::run_command("/usr/bin/python3 " + py.string() + " " + (dir / "mesh.xdmf").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int fibre_triangles = 0;
  for (const auto& s : m.subdomains)
    if (s.is_fibre) fibre_triangles += s.n_triangles();
  std::string first;
  for (int v : m.triangles[0]) first += " " + std::to_string(v);
  EXPECT_EQ(r.output, std::to_string(m.n_nodes()) + " " + std::to_string(m.triangles.size()) + " 8 " +
                          std::to_string(fibre_triangles) + first + "\n");
}

TEST(MeshFile, H5dumpReadsTheLayout) {
  testing::ScratchDir dir;
  const Scene scene = parse_scene(testing::scene_text(1, 1, 1, 0.3), dir / "s.toml");
  write_mesh(mesh::build_mesh(scene.geometry), scene, dir / "mesh.h5");
  const auto r = testing::run_command("h5dump -H " + (dir / "mesh.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : {"nodes", "triangles", "triangle_subdomain", "subdomain_is_fibre", "interface_pairs",
                           "glue_pairs", "left", "right", "bottom", "top"})
    EXPECT_NE(r.output.find(std::string("DATASET \"") + name + "\""), std::string::npos) << name;
}

TEST(MeshFile, CorruptOrForeignFilesAreRefused) {
  testing::ScratchDir dir;
  const Scene scene = parse_scene(testing::scene_text(1, 1, 1, 0.3), dir / "s.toml");
  write_mesh(mesh::build_mesh(scene.geometry), scene, dir / "mesh.h5");
  // Truncated: half the bytes.
  const auto size = std::filesystem::file_size(dir / "mesh.h5");
  std::filesystem::copy_file(dir / "mesh.h5", dir / "cut.h5");
  std::filesystem::resize_file(dir / "cut.h5", size / 2);
  EXPECT_THROW(read_mesh(dir / "cut.h5"), InputError);
  // Not HDF5 at all.
  dir.write("text.h5", "hello");
  EXPECT_THROW(read_mesh(dir / "text.h5"), InputError);
  // HDF5, but an index out of range.
  std::filesystem::copy_file(dir / "mesh.h5", dir / "bad.h5");
  {
    File f = File::open_write(dir / "bad.h5");
    f.remove("/mesh/glue_pairs");
    f.write("/mesh/glue_pairs", std::vector<std::int64_t>{0, 100000}, {1, 2});
  }
  try {
    read_mesh(dir / "bad.h5");
    FAIL() << "out-of-range index accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/mesh/glue_pairs: node index 100000 out of range"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(read_mesh(dir / "absent.h5"), InputError);
}

// A file whose periodic partners are broken, or whose sides are unequal, is refused with one
// line naming the file, the dataset and what is wrong.
TEST(MeshFile, BrokenPartnersAndUnequalSidesAreRefused) {
  testing::ScratchDir dir;
  const Scene scene = parse_scene(testing::scene_text(1, 1, 1, 0.3), dir / "s.toml");
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  write_mesh(m, scene, dir / "mesh.h5");
  const auto refused = [&](const std::string& name, const auto& edit, const std::string& message) {
    std::filesystem::copy_file(dir / "mesh.h5", dir / name);
    {
      File f = File::open_write(dir / name);
      edit(f);
    }
    try {
      read_mesh(dir / name);
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.what(), (dir / name).string() + ": " + message);
    }
  };
  std::vector<std::int64_t> pairs;
  for (const auto& [p, q, side] : m.periodic_pairs) pairs.insert(pairs.end(), {p, q, side});
  const auto write_pairs = [](File& f, std::vector<std::int64_t> rows) {
    f.remove("/mesh/periodic_pairs");
    f.write("/mesh/periodic_pairs", rows, {rows.size() / 3, 3});
  };
  auto swapped = pairs;
  std::swap(swapped[1 * 3 + 1], swapped[2 * 3 + 1]);
  refused(
      "swapped.h5", [&](File& f) { write_pairs(f, swapped); },
      "/mesh/periodic_pairs: pair 1: the partner of a point on the right side is not its copy on the left side");
  refused(
      "short.h5",
      [&](File& f) {
        write_pairs(f, {pairs.begin(), pairs.end() - 3});
      },
      "/mesh/periodic_pairs: point " + std::to_string(m.periodic_pairs.back().partner) +
          " on the bottom side is not in exactly one pair");
  auto far = pairs;
  far[0] = 100000;
  refused(
      "range.h5", [&](File& f) { write_pairs(f, far); },
      "/mesh/periodic_pairs: point 100000 out of range [0, " + std::to_string(m.n_points()) + ")");
  // A left point moved off the side with its mark and its boundary edges: the left side one point
  // short of the right.
  const int v = mesh::point_nodes(m)[mesh::side_points(m, mesh::left)[1]];
  refused(
      "unequal.h5",
      [&](File& f) {
        auto nodes = f.read_doubles("/mesh/nodes", {any_extent, 2});
        nodes[2 * v] = 1e-3;
        f.remove("/mesh/nodes");
        f.write("/mesh/nodes", nodes, {nodes.size() / 2, 2});
        auto sides = f.read_ints("/mesh/point_sides", {any_extent});
        sides[m.point_of[v]] = 0;
        f.remove("/mesh/point_sides");
        f.write("/mesh/point_sides", sides, {sides.size()});
        std::vector<std::int64_t> edges;  // p2: (a, b, mid)
        for (const mesh::Edge& e : m.boundary_edges[mesh::left])
          if (e.a != v && e.b != v && e.mid != v) edges.insert(edges.end(), {e.a, e.b, e.mid});
        f.remove("/mesh/boundary/left");
        f.write("/mesh/boundary/left", edges, {edges.size() / 3, 3});
      },
      "/mesh/point_sides: the right side has 9 points, the left side 8");
}

}  // namespace
}  // namespace dualcell::io
