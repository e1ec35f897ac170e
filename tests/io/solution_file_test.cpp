// solution.h5 written and read back (io/solution_file.hpp): a real solve with adhesion and some
// bonds broken, every attribute of qp::counter_fields, io::solver_count_fields, the seconds of
// feti::timing_fields and operator_profile_fields, io::kkt_fields,
// every column of rank_columns, u, the macro quantities, the fields (feti::solution_fields) and
// the bond state (io::read_bonds, the reader dualcell-solve --bonds uses) as written, bit for
// bit. The test walks the tables, so a field added to them is checked without an edit here.
#include "io/solution_file.hpp"

#include <gtest/gtest.h>

#include "feti/macro.hpp"
#include "io/hdf5.hpp"
#include "test_util.hpp"

namespace dualcell::io {
namespace {

std::vector<double> values(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

TEST(SolutionFile, EveryFieldComesBackAsWritten) {
  const Scene scene =
      parse_scene(testing::scene_text(2, 1, 1, 0.3,
                                      "[interface]\nnormal_strength = 0.02\ntangential_strength = 0.02\n"
                                      "[load]\nboundary = \"traction\"\n"),
                  "test.toml");
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  feti::ContactSolver solver(mesh, scene);
  const feti::Solution s = solver.solve({0.3, 0.05, 0.02}, solver.intact());
  ASSERT_TRUE(s.converged());
  ASSERT_GT(s.newly_broken, 0) << "the test needs a bond state with breaks";
  const feti::SolutionFields fields = feti::solution_fields(mesh, scene, s.u);
  RankTable ranks(2);
  for (std::size_t r = 0; r < ranks.size(); ++r) {
    int k = 1;  // every column its own value
    for (const RankColumn& c : rank_columns) {
      if (c.count) ranks[r].*c.count = static_cast<std::int64_t>(100 * r + k++);
      if (c.seconds) ranks[r].*c.seconds = 0.5 * static_cast<double>(100 * r + k++);
    }
  }
  Provenance provenance;
  provenance.mesh_file = "mesh.h5";
  provenance.mesh_hash = "0123456789abcdef";
  testing::ScratchDir dir;
  const auto file = dir / "solution.h5";
  write_solution(file, mesh, scene, s, fields, provenance, nullptr, &ranks);

  const File f = File::open_read(file);
  for (const qp::CounterField& field : qp::counter_fields)
    EXPECT_EQ(f.read_int_attribute_value("/solver", field.name), s.counters.*field.count) << field.name;
  for (const SolverCountField& field : solver_count_fields)
    EXPECT_EQ(f.read_int_attribute_value("/solver", field.attribute), s.*field.count) << field.attribute;
  for (const feti::TimingField& field : feti::timing_fields)
    EXPECT_EQ(f.read_double_attribute_value("/solver", std::string("seconds_") + field.name), s.seconds.*field.seconds)
        << field.name;
  for (const feti::OperatorProfileField& field : feti::operator_profile_fields)
    if (field.seconds) {
      EXPECT_EQ(f.read_double_attribute_value("/solver", std::string("seconds_qp_") + field.name),
                s.seconds.in_qp.*field.seconds)
          << field.name;
    }
  for (const KktField& field : kkt_fields)
    EXPECT_EQ(f.read_double_attribute_value("/kkt", field.attribute), s.kkt.*field.value) << field.attribute;
  for (const RankColumn& c : rank_columns) {
    const std::string name = std::string("/ranks/") + c.name;
    for (std::size_t r = 0; r < ranks.size(); ++r) {
      if (c.count) {
        EXPECT_EQ(f.read_ints(name, {ranks.size()})[r], ranks[r].*c.count) << name;
      } else {
        EXPECT_EQ(f.read_doubles(name, {ranks.size()})[r], ranks[r].*c.seconds) << name;
      }
    }
  }
  const hsize_t N = static_cast<hsize_t>(mesh.n_nodes()), T = mesh.triangles.size();
  EXPECT_EQ(f.read_doubles("/solution/u", {N, 2}), values(s.u.head(mesh.dim_u())));
  EXPECT_EQ(f.read_doubles("/macro/strain", {3}), values(s.strain));
  EXPECT_EQ(f.read_doubles("/macro/stress", {3}), values(s.sigma));
  EXPECT_EQ(f.read_doubles("/interface/opening", {mesh.interface_pairs.size()}), fields.opening);
  const Eigen::MatrixXd centroid_rows = fields.stress.centroid.transpose();  // row-major in the file
  EXPECT_EQ(f.read_doubles("/solution/element_stress", {T, 3}), values(centroid_rows.reshaped()));
  EXPECT_EQ(read_bonds(file, mesh, provenance.mesh_hash), s.bonds);
}

}  // namespace
}  // namespace dualcell::io
