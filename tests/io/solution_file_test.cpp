// solution.h5 written and read back (io/solution_file.hpp): a real solve with adhesion and some
// bonds broken, every attribute of qp::counter_fields, io::solver_count_fields, the seconds of
// feti::setup_timing_fields, qp_timing_fields and operator_profile_fields, io::kkt_fields,
// every column of rank_columns, u, the macro quantities, the fields (feti::solution_fields) and
// the bond state (io::read_bonds, the reader dualcell-solve --bonds uses) as written, bit for
// bit. The test walks the tables, so a field added to them is checked without an edit here.
#include "io/solution_file.hpp"

#include <gtest/gtest.h>

#include "feti/macro.hpp"
#include "io/fields_io.hpp"
#include "io/hdf5.hpp"
#include "io/record_walk.hpp"
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
  for (std::size_t r = 0; r < ranks.size(); ++r)
    testing::set_each_field(rank_columns, ranks[r], 100 * static_cast<int>(r));
  Provenance provenance;
  provenance.mesh_file = "mesh.h5";
  provenance.mesh_hash = "0123456789abcdef";
  testing::ScratchDir dir;
  const auto file = dir / "solution.h5";
  write_solution(file, mesh, scene, s, fields, provenance, nullptr, &ranks);

  const File f = File::open_read(file);
  // Each table read back through the one reader (io/fields_io.hpp) and compared member by member.
  qp::Counters counters;
  read_attributes(f, "/solver", qp::counter_fields, counters);
  testing::expect_same_fields(qp::counter_fields, counters, s.counters, "/solver");
  feti::Solution counts;
  read_attributes(f, "/solver", solver_count_fields, counts);
  testing::expect_same_fields(solver_count_fields, counts, s, "/solver");
  feti::Timings seconds;
  read_attributes(f, "/solver", feti::setup_timing_fields, seconds, "seconds_");
  read_attributes(f, "/solver", feti::qp_timing_fields, seconds, "seconds_");
  read_attributes(f, "/solver", feti::operator_profile_fields, seconds.in_qp, "seconds_qp_", "s");
  testing::expect_same_fields(feti::setup_timing_fields, seconds, s.seconds, "/solver seconds_");
  testing::expect_same_fields(feti::qp_timing_fields, seconds, s.seconds, "/solver seconds_");
  testing::expect_same_fields(feti::operator_profile_fields, seconds.in_qp, s.seconds.in_qp, "/solver seconds_qp_",
                              "s");
  feti::KktReport kkt;
  read_attributes(f, "/kkt", kkt_fields, kkt);
  testing::expect_same_fields(kkt_fields, kkt, s.kkt, "/kkt");
  RankTable ranks_back(ranks.size());
  read_columns(f, "/ranks", rank_columns, ranks_back, "/ranks");
  for (std::size_t r = 0; r < ranks.size(); ++r)
    testing::expect_same_fields(rank_columns, ranks_back[r], ranks[r], "/ranks row " + std::to_string(r));
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
