// law.h5: every field survives a write/read round trip (NaN included), the documented names are
// there, and missing, foreign, truncated or incomplete files are refused with one line naming
// the file and the object.
#include "io/law_file.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/hdf5.hpp"
#include "law/fields.hpp"
#include "law/reduced.hpp"
#include "law/synthetic_law.hpp"
#include "test_util.hpp"

namespace dualcell::io {
namespace {

using law::ComplianceFit;
using law::DirectionLaw;
using law::Law;

// Bitwise equal, so that NaN compares equal to NaN and −0 differs from 0.
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_matrix(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, const char* what) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_TRUE(same(a(i, j), b(i, j))) << what << "(" << i << "," << j << ")";
}

void expect_same_fit(const ComplianceFit& a, const ComplianceFit& b, const char* what) {
  expect_same_matrix(a.S, b.S, what);
  expect_same_matrix(a.S_se, b.S_se, what);
  EXPECT_EQ(a.rank, b.rank) << what;
  EXPECT_TRUE(same(a.relative_residual, b.relative_residual)) << what;
  ASSERT_EQ(a.direction_residual.size(), b.direction_residual.size()) << what;
  for (std::size_t i = 0; i < a.direction_residual.size(); ++i)
    EXPECT_TRUE(same(a.direction_residual[i], b.direction_residual[i])) << what << " direction " << i;
  EXPECT_EQ(a.symmetric_positive_definite, b.symmetric_positive_definite) << what;
  EXPECT_EQ(a.n_points, b.n_points) << what;
}

// Every field, listed by hand (not through law::direction_columns), so that a field missing
// from the table is caught too.
void expect_same_law(const Law& a, const Law& b) {
  ASSERT_EQ(a.directions.size(), b.directions.size());
  for (std::size_t i = 0; i < a.directions.size(); ++i) {
    const DirectionLaw &x = a.directions[i], &y = b.directions[i];
    for (auto [u, v, name] : {std::tuple{x.direction_deg, y.direction_deg, "direction_deg"},
                              {x.E_tension, y.E_tension, "E_tension"},
                              {x.E_tension_se, y.E_tension_se, "E_tension_se"},
                              {x.E_tension_r2, y.E_tension_r2, "E_tension_r2"},
                              {x.E_compression, y.E_compression, "E_compression"},
                              {x.E_compression_se, y.E_compression_se, "E_compression_se"},
                              {x.E_compression_r2, y.E_compression_r2, "E_compression_r2"},
                              {x.nu_tension, y.nu_tension, "nu_tension"},
                              {x.nu_tension_se, y.nu_tension_se, "nu_tension_se"},
                              {x.nu_compression, y.nu_compression, "nu_compression"},
                              {x.nu_compression_se, y.nu_compression_se, "nu_compression_se"},
                              {x.onset_stress, y.onset_stress, "onset_stress"},
                              {x.fuse_stress, y.fuse_stress, "fuse_stress"},
                              {x.fuse_stress_after, y.fuse_stress_after, "fuse_stress_after"},
                              {x.fuse_strain_jump, y.fuse_strain_jump, "fuse_strain_jump"},
                              {x.fuse_strain_ratio, y.fuse_strain_ratio, "fuse_strain_ratio"},
                              {x.E_after_fuse, y.E_after_fuse, "E_after_fuse"},
                              {x.E_after_fuse_se, y.E_after_fuse_se, "E_after_fuse_se"}})
      EXPECT_TRUE(same(u, v)) << name << " of direction " << i << ": " << u << " vs " << v;
    EXPECT_EQ(x.n_tension, y.n_tension);
    EXPECT_EQ(x.n_compression, y.n_compression);
  }
  expect_same_fit(a.tension, b.tension, "tension");
  expect_same_fit(a.compression, b.compression, "compression");
  EXPECT_TRUE(same(a.cone_rank_one_ratio, b.cone_rank_one_ratio));
  EXPECT_EQ(a.cone_wise_linear, b.cone_wise_linear);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(same(a.cone_normal(i), b.cone_normal(i)));
  for (const auto& [x, y] : {std::pair{&a.cone, &b.cone}, {&a.cone_after_fuse, &b.cone_after_fuse}}) {
    EXPECT_EQ(x->law.C_c, y->law.C_c);
    EXPECT_EQ(x->law.q, y->law.q);
    EXPECT_EQ(x->law.beta, y->law.beta);
    EXPECT_EQ(x->form, y->form);
    EXPECT_TRUE(same(x->relative_residual, y->relative_residual));
    EXPECT_TRUE(same(x->one_plane_residual, y->one_plane_residual));
    EXPECT_TRUE(same(x->struts_residual, y->struts_residual));
    ASSERT_EQ(x->direction_residual.size(), y->direction_residual.size());
    for (std::size_t i = 0; i < x->direction_residual.size(); ++i)
      EXPECT_TRUE(same(x->direction_residual[i], y->direction_residual[i]));
    EXPECT_EQ(x->n_points, y->n_points);
    EXPECT_EQ(x->ok, y->ok);
    EXPECT_EQ(x->message, y->message);
  }
  EXPECT_TRUE(same(a.cone_beta, b.cone_beta));
  EXPECT_EQ(a.onset.linear, b.onset.linear);
  EXPECT_EQ(a.onset.message, b.onset.message);
  EXPECT_EQ(a.onset.facets, b.onset.facets);
  EXPECT_EQ(a.onset.pair, b.onset.pair);
  EXPECT_EQ(a.onset.tangential, b.onset.tangential);
  EXPECT_EQ(a.onset.path_stress, b.onset.path_stress);
  ASSERT_EQ(a.onset.path_onset.size(), b.onset.path_onset.size());
  for (std::size_t k = 0; k < a.onset.path_onset.size(); ++k) {
    EXPECT_TRUE(same(a.onset.path_onset[k], b.onset.path_onset[k]));
    EXPECT_TRUE(same(a.onset.path_sweep_onset[k], b.onset.path_sweep_onset[k]));
  }
  EXPECT_TRUE(same(a.constituents.fibre_E, b.constituents.fibre_E));
  EXPECT_TRUE(same(a.constituents.fibre_nu, b.constituents.fibre_nu));
  EXPECT_TRUE(same(a.constituents.matrix_E, b.constituents.matrix_E));
  EXPECT_TRUE(same(a.constituents.matrix_nu, b.constituents.matrix_nu));
  EXPECT_TRUE(same(a.constituents.fibre_volume_fraction, b.constituents.fibre_volume_fraction));
  EXPECT_EQ(a.units, b.units);
  EXPECT_EQ(a.stress_state, b.stress_state);
  EXPECT_EQ(a.provenance.scene_text, b.provenance.scene_text);
  EXPECT_EQ(a.provenance.sweep_file, b.provenance.sweep_file);
  EXPECT_EQ(a.provenance.sweep_hash, b.provenance.sweep_hash);
  EXPECT_EQ(a.provenance.solver_options, b.provenance.solver_options);
  EXPECT_EQ(a.provenance.code_version, b.provenance.code_version);
}

// The message of the InputError that read_law throws, or a failure.
std::string refusal(const std::filesystem::path& file) {
  try {
    read_law(file);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << file << " was accepted";
  return "";
}

std::filesystem::path copy_of(const testing::ScratchDir& dir, const std::string& name) {
  std::filesystem::copy_file(dir / "law.h5", dir / name);
  return dir / name;
}

TEST(LawFile, RoundTripKeepsEveryFieldAndNaN) {
  testing::ScratchDir dir;
  const Law law = testing::synthetic_law();
  write_law(dir / "law.h5", law);
  const Law back = read_law(dir / "law.h5");
  expect_same_law(law, back);
  EXPECT_TRUE(std::isnan(back.directions[3].fuse_stress));
  EXPECT_TRUE(std::isnan(back.tension.S_se(2, 2)));
  // Only law.h5 in the folder: no temporary left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);
}

TEST(LawFile, HoldsTheDocumentedObjects) {
  testing::ScratchDir dir;
  write_law(dir / "law.h5", testing::synthetic_law());
  const io::File f = io::File::open_read(dir / "law.h5");
  // The names docs/reference/law-h5.md documents, and their shapes.
  for (const char* name : {"direction_deg", "E_tension", "E_compression", "nu_tension", "nu_compression", "fuse_stress",
                           "fuse_strain_jump", "E_after_fuse", "E_tension_se", "E_compression_se", "nu_tension_se",
                           "nu_compression_se", "E_after_fuse_se"})
    EXPECT_EQ(f.shape(std::string("/law/") + name), (std::vector<hsize_t>{4})) << name;
  for (const char* name : {"S_tension", "S_compression", "S_tension_se", "S_compression_se"})
    EXPECT_EQ(f.shape(std::string("/law/") + name), (std::vector<hsize_t>{3, 3})) << name;
  EXPECT_EQ(f.shape("/law/S_tension_rank"), (std::vector<hsize_t>{1}));
  for (const char* group : {"/law/cone", "/law/cone_after_fuse"}) {
    const std::string g = group;
    EXPECT_EQ(f.shape(g + "/C_c"), (std::vector<hsize_t>{3, 3})) << g;
    const hsize_t K = g == "/law/cone" ? 2 : 1;  // the synthetic law's planes
    EXPECT_EQ(f.shape(g + "/q"), (std::vector<hsize_t>{K, 3})) << g;
    EXPECT_EQ(f.shape(g + "/beta"), (std::vector<hsize_t>{K})) << g;
    for (const char* name : {"relative_residual", "one_plane_residual", "struts_residual", "n_points", "ok"})
      EXPECT_EQ(f.shape(g + "/" + name), (std::vector<hsize_t>{1})) << g << "/" << name;
    EXPECT_EQ(f.shape(g + "/direction_residual"), (std::vector<hsize_t>{4})) << g;
    EXPECT_TRUE(f.has_attribute(g, "message")) << g;
    EXPECT_TRUE(f.has_attribute(g, "form")) << g;
  }
  EXPECT_EQ(f.shape("/law/onset/facets"), (std::vector<hsize_t>{3, 3}));
  for (const char* name : {"pair", "tangential"})
    EXPECT_EQ(f.shape(std::string("/law/onset/") + name), (std::vector<hsize_t>{3})) << name;
  EXPECT_EQ(f.shape("/law/onset/path_stress"), (std::vector<hsize_t>{2, 3}));
  for (const char* name : {"onset", "sweep_onset"})
    EXPECT_EQ(f.shape(std::string("/law/onset/") + name), (std::vector<hsize_t>{2})) << name;
  EXPECT_EQ(f.read_int_attribute_value("/law/onset", "linear"), 1);
  EXPECT_TRUE(f.has_attribute("/law/onset", "message"));
  EXPECT_EQ(f.read_doubles("/law/S_tension", {3, 3})[1], testing::synthetic_law().tension.S(0, 1));
  EXPECT_EQ(f.read_string_attribute("/", "format"), "dualcell law 4");
  EXPECT_EQ(f.read_string_attribute("/law", "stress_state"), "plane strain");
  EXPECT_NE(f.read_string_attribute("/law", "shear_convention").find("engineering shear"), std::string::npos);
  for (const char* name : {"scene", "sweep_file", "sweep_hash", "solver_options", "code_version"})
    EXPECT_TRUE(f.has_attribute("/", name)) << name;
  EXPECT_TRUE(f.has_attribute("/law", "units"));
  EXPECT_EQ(f.read_double_attribute("/law", "fibre_E")[0], 72);
  // h5dump, an independent reader, sees the same.
  const auto r = testing::run_command("h5dump -d /law/fuse_stress " + (dir / "law.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("nan"), std::string::npos) << r.output;
}

TEST(LawFile, InconsistentLawIsABugOfTheCaller) {
  testing::ScratchDir dir;
  Law law = testing::synthetic_law();
  law.compression.direction_residual.pop_back();
  EXPECT_THROW(write_law(dir / "law.h5", law), std::invalid_argument);
  law.directions.clear();
  EXPECT_THROW(write_law(dir / "law.h5", law), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "law.h5"));
}

TEST(LawFile, ForeignTruncatedAndMissingFilesAreRefused) {
  testing::ScratchDir dir;
  write_law(dir / "law.h5", testing::synthetic_law());
  const auto size = std::filesystem::file_size(dir / "law.h5");
  for (const auto cut : {size / 2, size - 1, std::uintmax_t{100}}) {
    const auto file = copy_of(dir, "cut-" + std::to_string(cut) + ".h5");
    std::filesystem::resize_file(file, cut);
    const std::string message = refusal(file);
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_NE(refusal(dir.write("text.h5", "hello")).find("not an HDF5 file"), std::string::npos);
  EXPECT_NE(refusal(dir / "absent.h5").find("file not found"), std::string::npos);
  // An HDF5 file of another stage.
  {
    io::File f = io::File::create(dir / "other.h5");
    f.write_attribute("/", "format", std::string("dualcell sweep 1"));
    io::write_output(dir / "other.h5", f.close_to_image());
  }
  EXPECT_NE(refusal(dir / "other.h5").find("attribute format is 'dualcell sweep 1', expected 'dualcell law 4'"),
            std::string::npos);
  {
    io::File f = io::File::create(dir / "empty.h5");
    io::write_output(dir / "empty.h5", f.close_to_image());
  }
  EXPECT_NE(refusal(dir / "empty.h5").find("not a dualcell law file"), std::string::npos);
}

TEST(LawFile, EveryMissingObjectIsNamed) {
  testing::ScratchDir dir;
  write_law(dir / "law.h5", testing::synthetic_law());
  std::vector<std::string> datasets;
  for (const auto& c : law::direction_columns) datasets.push_back(c.name);
  for (const std::string p : {"S_tension", "S_compression"})
    for (const char* suffix : {"", "_se", "_rank", "_relative_residual", "_direction_residual", "_spd", "_n_points"})
      datasets.push_back(p + suffix);
  for (const char* name : {"cone_rank_one_ratio", "cone_wise_linear", "cone_normal", "cone_beta"})
    datasets.push_back(name);
  int index = 0;
  for (const auto& name : datasets) {
    const auto file = copy_of(dir, "missing-" + std::to_string(index++) + ".h5");
    io::File::open_write(file).remove("/law/" + name);
    const std::string message = refusal(file);
    EXPECT_NE(message.find(file.string() + ": /law/" + name + ": missing dataset"), std::string::npos) << message;
  }
  for (const auto& [object, attribute] :
       std::vector<std::pair<std::string, std::string>>{{"/law", "units"},
                                                        {"/law", "stress_state"},
                                                        {"/law", "shear_convention"},
                                                        {"/law", "fibre_E"},
                                                        {"/law", "fibre_volume_fraction"},
                                                        {"/", "scene"},
                                                        {"/", "sweep_hash"},
                                                        {"/", "code_version"}}) {
    const auto file = copy_of(dir, "attribute-" + std::to_string(index++) + ".h5");
    {
      // io::File has no attribute removal: the stages never need one.
      const io::Handle h5(H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
      ASSERT_GE(H5Adelete_by_name(h5.get(), object.c_str(), attribute.c_str(), H5P_DEFAULT), 0);
    }
    const std::string message = refusal(file);
    EXPECT_NE(message.find(object + ": missing attribute " + attribute), std::string::npos) << message;
  }
}

TEST(LawFile, WrongShapesAndValuesAreNamed) {
  testing::ScratchDir dir;
  write_law(dir / "law.h5", testing::synthetic_law());
  auto rewrite = [&](const std::string& name, const std::string& object, auto data, std::vector<hsize_t> dims) {
    const auto file = copy_of(dir, name);
    io::File f = io::File::open_write(file);
    f.remove(object);
    f.write(object, data, dims);
    return file;
  };
  std::string m = refusal(rewrite("short.h5", "/law/E_tension", std::vector<double>{1, 2, 3}, {3}));
  EXPECT_NE(m.find("/law/E_tension: expected shape (4) like /law/direction_deg, found (3)"), std::string::npos) << m;
  m = refusal(rewrite("flat.h5", "/law/S_compression", std::vector<double>(9, 1.0), {9}));
  EXPECT_NE(m.find("/law/S_compression: expected shape (3×3), found (9)"), std::string::npos) << m;
  m = refusal(rewrite("none.h5", "/law/direction_deg", std::vector<double>{}, {0}));
  EXPECT_NE(m.find("/law/direction_deg: expected a non-empty list of directions"), std::string::npos) << m;
  m = refusal(rewrite("count.h5", "/law/n_tension", std::vector<std::int64_t>{1, 2, -3, 4}, {4}));
  EXPECT_NE(m.find("/law/n_tension: entry 2 = -3 is not a count"), std::string::npos) << m;
  m = refusal(rewrite("flag.h5", "/law/S_tension_spd", std::vector<std::int64_t>{7}, {1}));
  EXPECT_NE(m.find("/law/S_tension_spd: value 7 out of range [0, 1]"), std::string::npos) << m;
  m = refusal(rewrite("type.h5", "/law/n_compression", std::vector<double>{1, 2, 3, 4}, {4}));
  EXPECT_NE(m.find("/law/n_compression: expected integer data"), std::string::npos) << m;
  const auto stress = copy_of(dir, "stress.h5");
  io::File::open_write(stress).write_attribute("/law", "stress_state", std::string("plane stress"));
  m = refusal(stress);
  EXPECT_NE(m.find("/law: attribute stress_state is 'plane stress', expected 'plane strain'"), std::string::npos) << m;
}

}  // namespace
}  // namespace dualcell::io

namespace dualcell::io {
namespace {

// The small cell and its fit and check come back as written, under the documented names; a file
// without one says why.
TEST(LawFile, TheSmallCellRoundTrips) {
  testing::ScratchDir dir;
  Law law = testing::synthetic_law();
  write_law(dir / "none.h5", law);
  law.small_note = "the cell has adhesion";
  write_law(dir / "note.h5", law);
  EXPECT_FALSE(read_law(dir / "note.h5").small);
  EXPECT_EQ(read_law(dir / "note.h5").small_note, "the cell has adhesion");
  EXPECT_EQ(read_law(dir / "none.h5").small_note, "law.h5 gives no reason");

  law::CondensedCell macro;
  macro.n_macro = 3;
  macro.volume = 2;
  macro.S0 = Eigen::Matrix3d{{2, 0.1, 0}, {0.1, 3, 0}, {0, 0, 4}};
  Eigen::MatrixXd Y(2, 3), H(2, 2);
  Y << 1, 2, 3, -1, 0.5, 0.25;
  H << 20, 1, 1, 30;
  law.small = law::cell_of_rows(macro, Y, H);
  law.small_fit = {0.02, 2, 1466, 0.015, 0.004, 321, 12.5};
  law.small_check.directions = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)};
  law.small_check.error = {0.01, 0.018};
  law.small_check.max_error = 0.018;
  law.small_check.rms_error = 0.015;
  law.small_check.worst = Eigen::Vector3d(0, 1, 0);
  write_law(dir / "law.h5", law);
  const Law back = read_law(dir / "law.h5");
  ASSERT_TRUE(back.small);
  EXPECT_EQ(back.small->Y, law.small->Y);
  EXPECT_EQ(back.small->H, law.small->H);
  EXPECT_EQ(back.small->S0, law.small->S0);
  EXPECT_EQ(back.small->G.rows(), 0);
  EXPECT_EQ(back.small_fit.rows, 2);
  EXPECT_EQ(back.small_fit.training_directions, 1466);
  EXPECT_EQ(back.small_fit.iterations, 321);
  EXPECT_EQ(back.small_fit.tolerance, 0.02);
  EXPECT_EQ(back.small_fit.training_max_error, 0.015);
  EXPECT_EQ(back.small_fit.seconds, 12.5);
  EXPECT_EQ(back.small_check.error, law.small_check.error);
  EXPECT_EQ(back.small_check.max_error, 0.018);
  const io::File f = io::File::open_read(dir / "law.h5");
  EXPECT_EQ(f.shape("/law/small/H"), (std::vector<hsize_t>{2, 2}));
  EXPECT_EQ(f.shape("/law/small_check/error"), (std::vector<hsize_t>{2}));
  for (const auto& field : law::small_cell_fit_fields)
    EXPECT_EQ(f.shape(std::string("/law/small_fit/") + field.name), (std::vector<hsize_t>{1})) << field.name;
}

}  // namespace
}  // namespace dualcell::io
