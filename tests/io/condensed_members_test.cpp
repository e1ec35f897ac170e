// Every member of law::CondensedCell's table (law/condensed_members.hpp) reaches every format of
// the cell and comes back: law.h5 (/law/cell, the group sweep.h5 has too), the cell's text (the
// members of the law; not what the condensation measured) and the JSON export. The cell's every
// member differs from a default cell's, so a member that a writer or reader leaves out comes
// back different and fails here, by name.
#include "law/condensed_members.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstring>
#include <map>
#include <sstream>
#include <type_traits>

#include "io/hdf5.hpp"
#include "io/law_export.hpp"
#include "io/law_file.hpp"
#include "io/record_walk.hpp"
#include "law/bond.hpp"
#include "law/cell_text.hpp"
#include "law/synthetic_law.hpp"
#include "test_util.hpp"

namespace dualcell::io {
namespace {

using law::CondensedCell;

// A small consistent cell: 2 macro components (3 is the default), 2 pairs of a normal and a tangential row, one
// fibre mode, the strain and the shear along the fibres, the temperature change; every member set,
// none to its default.
CondensedCell distinct_cell() {
  CondensedCell c;
  c.n_macro = 2;
  c.volume = 2.5;
  c.n_pairs = 2;
  c.S0 = Eigen::Matrix2d{{2, 0.1}, {0.1, 3}};
  c.Y.resize(4, 2);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 2; ++j) c.Y(i, j) = 0.1 * (i + 1) + 0.01 * (j + 1);
  const Eigen::MatrixXd A = c.Y * c.Y.transpose();
  c.H = A + Eigen::MatrixXd::Identity(4, 4);
  c.G = Eigen::RowVector4d{1, 2, 3, 4};
  c.tangential = {0, 1, 0, 1};
  c.pair = {0, 0, 1, 1};
  c.lower_bonded.resize(4), c.upper_bonded.resize(4), c.lower_broken.resize(4), c.upper_broken.resize(4);
  for (int r = 0; r < 4; ++r) {
    const auto kind = c.kind(r);
    const law::bond::Bounds bonded = law::bond::bounds(kind, law::bond::State::intact, 0.5 + r, 0.25 + r, 1.5);
    const law::bond::Bounds broken = law::bond::bounds(kind, law::bond::State::broken, 0, 0, 0);
    c.lower_bonded(r) = bonded.lower, c.upper_bonded(r) = bonded.upper;
    c.lower_broken(r) = broken.lower, c.upper_broken(r) = broken.upper;
  }
  c.bonded = {1, 0};
  c.longitudinal = 1;
  c.A33 = Eigen::Vector2d{-0.3, -0.2};
  c.C33 = Eigen::MatrixXd::Constant(1, 1, 4.5);
  c.y33 = Eigen::Vector4d{0.05, -0.01, 0.02, 0.0};
  c.shear = 2;
  c.shear_rows = 2;
  c.D0z = Eigen::Matrix2d{{1.5, 0.05}, {0.05, 1.25}};
  c.Yz = Eigen::Matrix2d{{0.2, -0.1}, {-0.2, 0.1}};
  c.Hz = Eigen::Matrix2d{{0.8, 0.1}, {0.1, 0.6}};
  c.Gz = Eigen::RowVector2d{1, 1};
  c.strength_z = Eigen::Vector2d{0.75, 1.75};
  c.pair_z = {1, 0};
  c.thermal = 1;
  c.AT = Eigen::Vector2d{2.5e-5, 2.7e-5};
  c.CT = Eigen::MatrixXd::Constant(1, 1, -1.2e-4);
  c.yT = Eigen::Vector4d{1e-6, -2e-6, 3e-6, 0.5e-6};
  c.reciprocity_error = 3e-13;
  c.seconds = 0.125;
  c.operator_applications = 17;
  return c;
}

// Each member's values as bytes (with the shape of an array), by name.
std::map<std::string, std::string> members(const CondensedCell& cell, bool law_only = false) {
  std::map<std::string, std::string> out;
  law::for_each_member(cell, [&](const law::Member& m, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const auto bytes = [](const void* p, std::size_t n) { return std::string(static_cast<const char*>(p), n); };
    if (law_only && m.measured) return;
    if constexpr (law::CountMember<T> || law::RealMember<T>)
      out[m.name] = bytes(&value, sizeof value);
    else if constexpr (law::ArrayMember<T>)
      out[m.name] = std::to_string(value.rows()) + "x" + std::to_string(value.cols()) + ":" +
                    bytes(value.data(), sizeof(double) * static_cast<std::size_t>(value.size()));
    else if constexpr (law::ListMember<T>)
      out[m.name] = bytes(value.data(), sizeof(typename T::value_type) * value.size());
  });
  return out;
}

void expect_same_members(const CondensedCell& back, const CondensedCell& cell, const char* format,
                         bool law_only = false) {
  const auto expected = members(cell, law_only), found = members(back, law_only);
  for (const auto& [name, value] : expected) EXPECT_EQ(found.at(name), value) << format << ": " << name;
}

TEST(CondensedMembers, EveryMemberDiffersFromADefaultCellAndTheCellIsConsistent) {
  const CondensedCell cell = distinct_cell();
  ASSERT_EQ(law::consistency_problem(cell), "");
  const auto defaults = members(CondensedCell{});
  for (const auto& [name, value] : members(cell)) EXPECT_NE(defaults.at(name), value) << name;
}

TEST(CondensedMembers, EveryMemberReachesLawH5AndBack) {
  testing::ScratchDir dir;
  law::Law law = testing::synthetic_law();
  law.cell = distinct_cell();
  write_law(dir / "law.h5", law);
  expect_same_members(*read_law(dir / "law.h5").cell, *law.cell, "law.h5");
}

TEST(CondensedMembers, EveryMemberOfTheLawReachesTheCellTextAndBack) {
  const CondensedCell cell = distinct_cell();
  std::ostringstream out;
  law::write_cell_text(out, cell);
  std::istringstream in(out.str());
  std::string error;
  const CondensedCell back = law::read_cell_text(in, error);
  ASSERT_EQ(error, "");
  expect_same_members(back, cell, "cell text", true);
}

TEST(CondensedMembers, EveryMemberReachesTheJson) {
  law::Law law = testing::synthetic_law();
  law.cell = distinct_cell();
  const std::string json = law_json(law);
  const std::string cell = json.substr(json.find("\"cell\": {"));
  law::for_each_member(*law.cell, [&](const law::Member& m, const auto& value) {
    if constexpr (!std::is_same_v<std::remove_cvref_t<decltype(value)>, law::TextSize>) {
      EXPECT_NE(cell.find("\"" + std::string(m.name) + "\": "), std::string::npos) << m.name;
    }
  });
}

// A cell without the strain along the fibres (L = 0, the transverse law): law.h5 and the JSON
// leave its members out, the cell text writes them empty, and each reads back as that cell.
TEST(CondensedMembers, ACellWithoutTheStrainAlongTheFibresLeavesItsMembersOut) {
  CondensedCell cell = distinct_cell();
  cell.longitudinal = 0;
  cell.A33.resize(0, 0), cell.C33.resize(0, 0), cell.y33.resize(0, 0);
  cell.CT.resize(0, 1);  // σ33 per kelvin: none without ε33
  ASSERT_EQ(law::consistency_problem(cell), "");
  testing::ScratchDir dir;
  law::Law law = testing::synthetic_law();
  law.cell = cell;
  write_law(dir / "law.h5", law);
  EXPECT_FALSE(File::open_read(dir / "law.h5").exists("/law/cell/A33"));
  const CondensedCell back = *read_law(dir / "law.h5").cell;
  EXPECT_EQ(back.longitudinal, 0);
  EXPECT_EQ(back.A33.size() + back.C33.size() + back.y33.size(), 0);
  const std::string json = law_json(law);
  EXPECT_EQ(json.find("\"A33\""), std::string::npos);
  std::ostringstream out;
  law::write_cell_text(out, cell);
  std::istringstream in(out.str());
  std::string error;
  const CondensedCell text = law::read_cell_text(in, error);
  ASSERT_EQ(error, "");
  EXPECT_EQ(text.longitudinal, 0);
  // A cell that says L = 1 without its arrays is refused, by name.
  cell.longitudinal = 1;
  EXPECT_NE(law::consistency_problem(cell).find("A33"), std::string::npos) << law::consistency_problem(cell);
}

// The temperature change is left out of every format where the cell has none (law.h5, JSON; the
// text keeps its version 2 or 4), and a cell with it writes the text's version 5, which has the
// shear's members too (shear 0 where it has none) and reads back; its count is checked.
TEST(CondensedMembers, ACellWithoutTheTemperatureChangeLeavesItsMembersOut) {
  testing::ScratchDir dir;
  law::Law law = testing::synthetic_law();
  CondensedCell cell = distinct_cell();
  cell.thermal = 0;
  cell.AT.resize(0, 0), cell.CT.resize(0, 0), cell.yT.resize(0, 0);
  ASSERT_EQ(law::consistency_problem(cell), "");
  law.cell = cell;
  write_law(dir / "cold.h5", law);
  EXPECT_FALSE(File::open_read(dir / "cold.h5").exists("/law/cell/thermal"));
  EXPECT_FALSE(File::open_read(dir / "cold.h5").exists("/law/cell/AT"));
  EXPECT_EQ(read_law(dir / "cold.h5").cell->thermal, 0);
  EXPECT_EQ(law_json(law).find("\"yT\""), std::string::npos);
  std::ostringstream out;
  law::write_cell_text(out, cell);
  EXPECT_EQ(out.str().rfind("dualcell cell law 4\n", 0), 0u);
  EXPECT_EQ(out.str().find("\nAT"), std::string::npos);
  // With ΔT and without the shear along the fibres (plane strain): version 5, shear 0.
  cell = distinct_cell();
  cell.shear = cell.shear_rows = 0;
  cell.D0z.resize(0, 0), cell.Yz.resize(0, 0), cell.Hz.resize(0, 0), cell.Gz.resize(0, 0);
  cell.strength_z.resize(0), cell.pair_z.clear();
  ASSERT_EQ(law::consistency_problem(cell), "");
  std::ostringstream text;
  law::write_cell_text(text, cell);
  ASSERT_EQ(text.str().rfind("dualcell cell law 5\n", 0), 0u);
  std::istringstream in(text.str());
  std::string error;
  const CondensedCell back = law::read_cell_text(in, error);
  ASSERT_EQ(error, "");
  EXPECT_EQ(back.shear, 0);
  EXPECT_EQ(back.thermal, 1);
  EXPECT_EQ(back.AT, cell.AT);
  EXPECT_EQ(back.yT, cell.yT);
  cell.thermal = 2;
  EXPECT_EQ(law::consistency_problem(cell), "thermal is 2, not in [0, 1]");
}

// The shear along the fibres is left out of every format where the cell has none (law.h5, JSON;
// the text stays version 2, as such a cell's always was), and its rows where no bond carries
// shear (no adhesion: ⟨τ⟩ = D0z Γ); its counts are checked.
TEST(CondensedMembers, ACellWithoutTheShearAlongTheFibresLeavesItsMembersOut) {
  testing::ScratchDir dir;
  law::Law law = testing::synthetic_law();
  CondensedCell cell = distinct_cell();
  cell.shear_rows = 0;
  cell.Yz.resize(0, 0), cell.Hz.resize(0, 0), cell.Gz.resize(0, 0), cell.strength_z.resize(0);
  cell.pair_z.clear();
  ASSERT_EQ(law::consistency_problem(cell), "");
  law.cell = cell;
  write_law(dir / "rows.h5", law);
  EXPECT_TRUE(File::open_read(dir / "rows.h5").exists("/law/cell/D0z"));
  EXPECT_FALSE(File::open_read(dir / "rows.h5").exists("/law/cell/Hz"));
  const CondensedCell rows = *read_law(dir / "rows.h5").cell;
  EXPECT_EQ(rows.shear, 2);
  EXPECT_EQ(rows.shear_rows, 0);
  EXPECT_EQ(rows.D0z, cell.D0z);
  cell.shear = 0;
  cell.D0z.resize(0, 0);
  cell.thermal = 0;  // (a cell with ΔT writes the text's version 5: below)
  cell.AT.resize(0, 0), cell.CT.resize(0, 0), cell.yT.resize(0, 0);
  ASSERT_EQ(law::consistency_problem(cell), "");
  law.cell = cell;
  write_law(dir / "none.h5", law);
  EXPECT_FALSE(File::open_read(dir / "none.h5").exists("/law/cell/shear"));
  EXPECT_EQ(read_law(dir / "none.h5").cell->shear, 0);
  EXPECT_EQ(law_json(law).find("\"D0z\""), std::string::npos);
  std::ostringstream out;
  law::write_cell_text(out, cell);
  EXPECT_EQ(out.str().rfind("dualcell cell law 2\n", 0), 0u);
  EXPECT_EQ(out.str().find("shear"), std::string::npos);
  cell.shear = 1;
  EXPECT_EQ(law::consistency_problem(cell), "shear: is 1, not 0 or 2");
  cell = distinct_cell();
  cell.pair_z = {0, 2};
  EXPECT_EQ(law::consistency_problem(cell), "pair_z: 2 is not a pair index (row 1)");
  // The text of the shear with a row per pair and no pair_z (version 3) is refused, not misread.
  std::ostringstream text;
  CondensedCell no_thermal = distinct_cell();
  no_thermal.thermal = 0;
  no_thermal.AT.resize(0, 0), no_thermal.CT.resize(0, 0), no_thermal.yT.resize(0, 0);
  law::write_cell_text(text, no_thermal);
  ASSERT_EQ(text.str().rfind("dualcell cell law 4\n", 0), 0u);
  std::istringstream older("dualcell cell law 3\n" + text.str().substr(text.str().find('\n') + 1));
  std::string error;
  law::read_cell_text(older, error);
  EXPECT_NE(error.find("no pair_z, an older layout: export the law again"), std::string::npos) << error;
  // Hz singular on Gz q = 0 (its rows repeated): two pairs that would slip as one.
  cell = distinct_cell();
  cell.Hz = Eigen::Matrix2d::Constant(0.5);
  cell.Gz = Eigen::RowVector2d{1, 1};
  EXPECT_NE(law::consistency_problem(cell).find("the shear rows' Hz is not positive definite on Gz q = 0"),
            std::string::npos)
      << law::consistency_problem(cell);
}

// The exact law's replay check (law::cell_replay_fields) beside it: every member its own value,
// through law.h5 and back and into the JSON.
TEST(CellReplayFields, EveryMemberHasItsRow) {
  // A member added without a row breaks the build here (the binding names every member).
  auto [points, max_error, rms_error, worst_path, worst_step, break_mismatches, limit] = law::CellReplay{};
  (void)points, (void)max_error, (void)rms_error, (void)worst_path, (void)worst_step, (void)break_mismatches,
      (void)limit;
  EXPECT_EQ(std::size(law::cell_replay_fields), 7u);
}

TEST(CellReplayFields, EveryMemberReachesLawH5AndTheJson) {
  testing::ScratchDir dir;
  law::Law law = testing::synthetic_law();
  law.cell = distinct_cell();
  testing::set_each_field(law::cell_replay_fields, law.cell_replay, 3);
  write_law(dir / "law.h5", law);
  const law::Law back = read_law(dir / "law.h5");
  const std::string json = law_json(law);
  const std::string replay = json.substr(json.find("\"cell_replay\": {"));
  testing::expect_same_fields(law::cell_replay_fields, back.cell_replay, law.cell_replay, "/law/cell_replay");
  for (const auto& field : law::cell_replay_fields) {
    const std::string key = std::string(1, '"') + field.name + "\": ";
    EXPECT_NE(replay.find(key), std::string::npos) << field.name;
  }
}

// The messages the readers give come from the table's rules: the member, then what.
TEST(CondensedMembers, ConsistencyNamesTheMemberAndTheRule) {
  CondensedCell cell = distinct_cell();
  cell.pair[3] = 7;
  EXPECT_EQ(law::consistency_problem(cell), "pair: 7 is not a pair index (row 3)");
  cell = distinct_cell();
  cell.H(0, 1) += 1;
  EXPECT_EQ(law::consistency_problem(cell), "H is not symmetric");
  cell = distinct_cell();
  cell.Y(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(law::consistency_problem(cell), "non-finite entries");
  cell = distinct_cell();
  cell.lower_bonded(1) = 0.5;
  EXPECT_EQ(law::consistency_problem(cell), "lower_bonded: row 1: its bounds do not hold 0");
  cell = distinct_cell();
  cell.bonded.pop_back();
  EXPECT_EQ(law::consistency_problem(cell), "bonded is not n_pairs long");
  cell = distinct_cell();
  cell.n_macro = 4;
  EXPECT_EQ(law::consistency_problem(cell), "n_macro is 4, not in [2, 3]");
  cell = distinct_cell();
  cell.volume = 1e-150;
  EXPECT_EQ(law::consistency_problem(cell), "volume is 1e-150, not within 1e-100 … 1e100");
  cell = distinct_cell();
  cell.Y *= 1e200;
  EXPECT_EQ(law::consistency_problem(cell), "Y: its largest entry is 4.2e+199, not within 1e-100 … 1e100");
}

// A law read from a file is convex or refused: 𝓗 = [|Ω|S0 −Yᵀ; −Y H] positive definite on G p = 0.
TEST(CondensedMembers, ANonConvexCellIsRefused) {
  CondensedCell cell = distinct_cell();
  cell.H = -cell.H;  // negative definite: its diagonal already says so
  EXPECT_EQ(law::consistency_problem(cell),
            "the energy [|Ω|S0 −Yᵀ; −Y H] has a diagonal entry ≤ 0 (row 2): the law is not convex");
  // Every block positive definite on its own, the coupling too strong: |Ω|S0 − Yᵀ H⁻¹ Y is not.
  cell = distinct_cell();
  cell.S0 *= 1e-3;
  EXPECT_NE(law::consistency_problem(cell).find("is not positive definite on G p = 0"), std::string::npos)
      << law::consistency_problem(cell);
  // Singular on ker G (a row of H repeated with its Y row: two rows that open as one).
  cell = distinct_cell();
  cell.H.row(3) = cell.H.row(2);
  cell.H.col(3) = cell.H.col(2);
  cell.Y.row(3) = cell.Y.row(2);
  cell.G(0, 3) = cell.G(0, 2);
  EXPECT_NE(law::consistency_problem(cell).find("is not positive definite on G p = 0"), std::string::npos)
      << law::consistency_problem(cell);
  // The same cell in other units of length: still convex (the check is equilibrated).
  cell = distinct_cell();
  cell.S0 *= 1e40, cell.volume *= 1e-40;
  EXPECT_EQ(law::consistency_problem(cell), "");
}

// A law.h5 with the shear along the fibres written before pair_z (one shear row per pair, in
// order) reads with that meaning; the cell's text of that time (version 3) is refused instead
// (above), since the umat's card must be exported again anyway.
TEST(CondensedMembers, AFileOfShearRowsWithoutPairZReadsOneRowPerPair) {
  testing::ScratchDir dir;
  law::Law law = testing::synthetic_law();
  CondensedCell cell = distinct_cell();
  cell.pair_z = {0, 1};
  law.cell = cell;
  write_law(dir / "old.h5", law);
  const hid_t f = H5Fopen((dir / "old.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  ASSERT_GE(H5Ldelete(f, "/law/cell/pair_z", H5P_DEFAULT), 0);
  H5Fclose(f);
  EXPECT_EQ(read_law(dir / "old.h5").cell->pair_z, (std::vector<int>{0, 1}));
}

}  // namespace
}  // namespace dualcell::io
