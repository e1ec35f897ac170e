// structure.h5 written and read back (io/structure_file.hpp): every column of
// io::structure_step_columns, the reactions and every step's fields as written, bit for bit, on
// steps whose every member has its own value. The test walks the table, so a column added to it
// is checked without an edit here.
#include "io/structure_file.hpp"

#include <gtest/gtest.h>

#include "io/fields_io.hpp"
#include "io/hdf5.hpp"
#include "io/record_walk.hpp"
#include "test_util.hpp"

namespace dualcell::io {
namespace {

TEST(StructureFile, EveryColumnAndFieldComesBackAsWritten) {
  StructureScene scene;
  scene.nx = 3;
  scene.ny = 2;
  scene.elements_per_cell = 2;
  scene.element = Element::p2;
  const structure::StructureMesh mesh = structure::build_structure_mesh(scene);
  const Eigen::Index N = mesh.nodes.rows(), T = mesh.triangles.rows();
  std::vector<structure::StepResult> steps(3);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    structure::StepResult& s = steps[k];
    testing::set_each_field(structure_step_columns, s, 10 * static_cast<int>(k));  // every member its own value
    double v = 10.0 * static_cast<double>(k) + 20;
    for (auto& R : s.reactions) R = {v + 0.5, v + 1}, v += 1;
    s.u = Eigen::VectorXd::LinSpaced(2 * N, v, v + 1);
    s.stress = Eigen::MatrixXd::Random(T, 3);
    s.open.assign(T, static_cast<std::uint32_t>(k + 1));
    s.fused.assign(T, static_cast<std::uint8_t>(k % 2));
    s.broken.assign(T, 0.25f * static_cast<float>(k));
  }
  Provenance provenance;
  provenance.law_file = "law.h5";
  provenance.law_hash = "0123456789abcdef";
  testing::ScratchDir dir;
  const auto file = dir / "structure.h5";
  write_structure(file, mesh, steps, 0.75, "cell", "point", provenance);

  const File f = File::open_read(file);
  const auto S = static_cast<hsize_t>(steps.size());
  std::vector<structure::StepResult> back(steps.size());
  read_columns(f, "/steps", structure_step_columns, back, "/steps/factor");
  for (std::size_t k = 0; k < steps.size(); ++k)
    testing::expect_same_fields(structure_step_columns, back[k], steps[k], "/steps row " + std::to_string(k));
  const auto reactions = f.read_doubles("/steps/reactions", {S, 10});
  for (std::size_t k = 0; k < steps.size(); ++k)
    for (int e = 0; e < 5; ++e)
      for (int c = 0; c < 2; ++c) EXPECT_EQ(reactions[10 * k + 2 * e + c], steps[k].reactions[e](c));
  EXPECT_EQ(f.read_double_attribute_value("/steps", "first_fuse_factor"), 0.75);
  EXPECT_EQ(f.read_string_attribute("/", "law_form"), "cell");
  EXPECT_EQ(f.read_string_attribute("/", "bond_unit"), "point");
  const auto Th = static_cast<hsize_t>(T), Nh = static_cast<hsize_t>(N);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    char group[32];
    std::snprintf(group, sizeof group, "/steps/%03zu", k);
    const std::string g = group;
    const std::vector<double> u(steps[k].u.data(), steps[k].u.data() + steps[k].u.size());
    EXPECT_EQ(f.read_doubles(g + "/displacement", {Nh, 2}), u);
    const auto stress = f.read_doubles(g + "/stress", {Th, 3});
    for (Eigen::Index t = 0; t < T; ++t)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(stress[3 * t + c], steps[k].stress(t, c));
    EXPECT_EQ(f.read_ints(g + "/open", {Th}), std::vector<std::int64_t>(steps[k].open.begin(), steps[k].open.end()));
    EXPECT_EQ(f.read_ints(g + "/fused", {Th}), std::vector<std::int64_t>(steps[k].fused.begin(), steps[k].fused.end()));
    EXPECT_EQ(f.read_doubles(g + "/broken", {Th}), std::vector<double>(steps[k].broken.begin(), steps[k].broken.end()));
  }
}

}  // namespace
}  // namespace dualcell::io
