// The exact law in the user material (layout 2, src/umat/cell_umat.h) against the library's
// own evaluation (law::CellEvaluator) along a loading path through the debond cascade, with the
// state variables carried from call to call as a code carries them over converged increments;
// the text file that carries the cell, bit for bit; and the refusals.
#include "umat/cell_umat.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/hash.hpp"
#include "core/text.hpp"
#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "io/law_export.hpp"
#include "law/cell_text.hpp"
#include "mesh/mesh.hpp"
#include "test_util.hpp"
#include "umat/umat_signature.hpp"

namespace dualcell::law {
namespace {

// A periodic p1 cell with adhesion (16 pairs, 32 rows).
CondensedCell adhesive_cell() {
  Scene s = parse_scene(testing::scene_text(1, 1, 2, 0.3), "test.toml");
  s.geometry.element = Element::p1;
  s.fibre = {30.0, 0.22};
  s.matrix = {1.0, 0.35};
  s.load.boundary = Boundary::periodic;
  s.interface.normal_strength = 0.01;
  s.interface.tangential_strength = 0.01;
  const mesh::Mesh mesh = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(mesh, s);
  return feti::condense(solver.setup());
}

struct Call {
  Eigen::Vector3d stress;
  Eigen::Matrix3d tangent;
  double energy, pnewdt;
  double sigma33;
};

// One umat call at the plane strain (ε11, ε22, γ12) with ε33 = 1e-4, the state `statev` in and out.
Call call(const std::vector<double>& props, const Eigen::Vector3d& e, std::vector<double>& statev) {
  double stress[6] = {}, ddsdde[36], sse = 0, spd = 0, scd = 0, rpl = 0, ddsddt[6], drplde[6];
  double drpldt = 0, time[2] = {}, dtime = 1, temp = 0, dtemp = 0, predef = 0, dpred = 0, coords[3] = {}, drot[9] = {};
  double pnewdt = 1, celent = 1, dfgrd0[9] = {}, dfgrd1[9] = {};
  const double stran[6] = {0.5 * e(0), 0.5 * e(1), 0, 0.5 * e(2), 0, 0};
  const double dstran[6] = {0.5 * e(0), 0.5 * e(1), 1e-4, 0.5 * e(2), 0, 0};
  const int ndi = 3, nshr = 3, ntens = 6, nstatv = static_cast<int>(statev.size());
  const int nprops = static_cast<int>(props.size()), noel = 1, npt = 1, layer = 1, kspt = 1, kstep = 1, kinc = 1;
  umat_(stress, statev.data(), ddsdde, &sse, &spd, &scd, &rpl, ddsddt, drplde, &drpldt, stran, dstran, time, &dtime,
        &temp, &dtemp, &predef, &dpred, "ABAQUS_CELL", &ndi, &nshr, &ntens, &nstatv, props.data(), &nprops, coords,
        drot, &pnewdt, &celent, dfgrd0, dfgrd1, &noel, &npt, &layer, &kspt, &kstep, &kinc, 11);
  Call c;
  const int in_plane[3] = {0, 1, 3};
  for (int i = 0; i < 3; ++i) {
    c.stress(i) = stress[in_plane[i]];
    for (int j = 0; j < 3; ++j) c.tangent(i, j) = ddsdde[in_plane[i] + 6 * in_plane[j]];
  }
  c.energy = sse, c.pnewdt = pnewdt, c.sigma33 = stress[2];
  return c;
}

TEST(CellUmat, TheCellTextGivesTheSameCellBitForBit) {
  const CondensedCell cell = adhesive_cell();
  std::ostringstream out;
  write_cell_text(out, cell);
  std::istringstream in(out.str());
  std::string error;
  const CondensedCell back = read_cell_text(in, error);
  ASSERT_EQ(error, "");
  EXPECT_EQ(back.S0, cell.S0);
  EXPECT_EQ(back.Y, cell.Y);
  EXPECT_EQ(back.H, cell.H);
  EXPECT_EQ(back.G, cell.G);
  EXPECT_EQ(back.lower_bonded, cell.lower_bonded);
  EXPECT_EQ(back.upper_broken, cell.upper_broken);  // +inf where a broken normal row is unbounded
  EXPECT_EQ(back.pair, cell.pair);
  EXPECT_EQ(back.tangential, cell.tangential);
  EXPECT_EQ(back.bonded, cell.bonded);
  EXPECT_EQ(back.volume, cell.volume);
  // A cut file and a wrong number are refused with the keyword.
  const std::string text = out.str();
  std::istringstream cut(text.substr(0, text.find("\nH ")));
  read_cell_text(cut, error);
  EXPECT_NE(error.find("'H'"), std::string::npos) << error;
  std::string wrong = text;
  wrong[wrong.find("volume ") + 7] = 'x';
  std::istringstream bad(wrong);
  error.clear();
  read_cell_text(bad, error);
  EXPECT_NE(error.find("volume"), std::string::npos) << error;
}

TEST(CellUmat, EqualsTheLibraryAlongAPathThroughTheCascade) {
  testing::ScratchDir dir;
  setenv("DUALCELL_CELL_DIR", dir.path().c_str(), 1);
  const CondensedCell cell = adhesive_cell();
  const std::string text = [&] {
    std::ostringstream out;
    write_cell_text(out, cell);
    return out.str();
  }();
  std::ofstream(dir / io::umat_cell_file(7001)) << text;
  // The card's constants, as dualcell-export writes them.
  Law law;
  law.constituents = with_isotropic_axes({30.0, 0.22, 1.0, 0.35, 0.28, 1.0});
  law.cell = cell;
  const std::uint64_t hash = text_hash_value(text);
  const std::string card = io::law_umat_cell(law, law::LawForm::cell, "CELL", 7001, hash, "law.h5");
  const std::string depvar = std::string("*DEPVAR\n").append(std::to_string(1 + cell.n_pairs + 3 + cell.n_rows()));
  ASSERT_NE(card.find(depvar), std::string::npos) << card;
  const OutOfPlane z = rule_of_mixtures(law);
  const double high = static_cast<double>(hash >> 32), low = static_cast<double>(hash & 0xffffffffULL);
  const std::vector<double> props = {2, 7001, z.E3, z.G13, z.G23, high, low};
  ASSERT_NE(card.find("CONSTANTS=7"), std::string::npos) << card;
  ASSERT_NE(card.find(formatted("%.12e", high) + ", " + formatted("%.12e", low)), std::string::npos) << card;
  std::vector<double> statev(1 + cell.n_pairs + 3 + cell.n_rows(), 0.0);

  CellEvaluator library(cell);
  CellHistory h = library.unloaded();
  const Eigen::Vector3d direction(1.0, 0.2, 0.3);
  int broken_seen = 0;
  for (const double scale : {1e-3, 5e-3, 1e-2, 2e-2, 4e-2, 1e-2, 0.0}) {
    const Eigen::Vector3d e = scale * direction;
    const Call c = call(props, e, statev);
    const CellResponse r = library.at_strain(e, h);
    ASSERT_TRUE(r.ok) << r.message;
    ASSERT_EQ(c.pnewdt, 1) << scale;
    // The same QP from the same warm start: round-off apart.
    EXPECT_LE((c.stress - r.stress).norm(), 1e-12 * std::max(r.stress.norm(), 1e-300)) << scale;
    EXPECT_LE((c.tangent - r.tangent).norm(), 1e-12 * r.tangent.norm()) << scale;
    EXPECT_NEAR(c.energy, r.energy + 0.5 * z.E3 * 1e-8, 1e-12 * std::max(c.energy, 1e-300)) << scale;
    EXPECT_NEAR(c.sigma33, z.E3 * 1e-4, 1e-15);
    EXPECT_EQ(statev[0], r.broken) << scale;
    int flags = 0;
    for (int p = 0; p < cell.n_pairs; ++p) flags += statev[1 + p] >= 0.5;
    EXPECT_EQ(flags, r.broken);
    broken_seen = std::max(broken_seen, r.broken);
  }
  EXPECT_GT(broken_seen, 0) << "the path must reach past the first break";
  EXPECT_EQ(statev[0], broken_seen) << "bonds never heal";

  // A law whose file is missing, and a state too short: a smaller increment asked, nothing else.
  std::vector<double> state(statev.size(), 0.0);
  EXPECT_EQ(call({2, 7002, 1, 1, 1, 0, 0}, direction * 1e-3, state).pnewdt, 0.25);
  std::vector<double> short_state(3, 0.0);
  EXPECT_EQ(call(props, direction * 1e-3, short_state).pnewdt, 0.25);
  // A card written before the hash (5 constants), and one whose hash is not the file's: refused,
  // each with its line (the first once was silent).
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(call({2, 7001, z.E3, z.G13, z.G23}, direction * 1e-3, state).pnewdt, 0.25);
  const std::string told = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(told.find("dualcell umat: a layout-2 card (the exact law) with fewer than 7 constants"), std::string::npos)
      << told;
  std::vector<double> other = props;
  other[6] = low == 0 ? 1 : low - 1;
  EXPECT_EQ(call(other, direction * 1e-3, state).pnewdt, 0.25);
  other[6] = 0.5;  // not an integer: no hash at all
  EXPECT_EQ(call(other, direction * 1e-3, state).pnewdt, 0.25);
}

// One umat call at the 3D strain e = (ε11, ε22, ε33, γ12, γ13, γ23): σ (6) and the tangent.
struct Call6 {
  Eigen::Matrix<double, 6, 1> stress;
  Eigen::Matrix<double, 6, 6> tangent;
  double energy, pnewdt;
};
// `temperature`: the code's temperature at the start of the increment (its change over it 0).
Call6 call6(const std::vector<double>& props, const Eigen::Matrix<double, 6, 1>& e, std::vector<double>& statev,
            double temperature = 0) {
  double stress[6] = {}, ddsdde[36], sse = 0, spd = 0, scd = 0, rpl = 0, ddsddt[6], drplde[6];
  double drpldt = 0, time[2] = {}, dtime = 1, temp = temperature, dtemp = 0, predef = 0, dpred = 0, coords[3] = {};
  double drot[9] = {};
  double pnewdt = 1, celent = 1, dfgrd0[9] = {}, dfgrd1[9] = {};
  double stran[6], dstran[6];
  for (int i = 0; i < 6; ++i) stran[i] = dstran[i] = 0.5 * e(i);
  const int ndi = 3, nshr = 3, ntens = 6, nstatv = static_cast<int>(statev.size());
  const int nprops = static_cast<int>(props.size()), noel = 1, npt = 1, layer = 1, kspt = 1, kstep = 1, kinc = 1;
  umat_(stress, statev.data(), ddsdde, &sse, &spd, &scd, &rpl, ddsddt, drplde, &drpldt, stran, dstran, time, &dtime,
        &temp, &dtemp, &predef, &dpred, "ABAQUS_PLY", &ndi, &nshr, &ntens, &nstatv, props.data(), &nprops, coords, drot,
        &pnewdt, &celent, dfgrd0, dfgrd1, &noel, &npt, &layer, &kspt, &kstep, &kinc, 10);
  Call6 c;
  for (int i = 0; i < 6; ++i) {
    c.stress(i) = stress[i];
    for (int j = 0; j < 6; ++j) c.tangent(i, j) = ddsdde[i + 6 * j];
  }
  c.energy = sse, c.pnewdt = pnewdt;
  return c;
}

// A whole ply's cell (the strain and the shears along the fibres, bonds of strength 0.01) in the
// cell file of `id` in `dir` (DUALCELL_CELL_DIR), its layout-3 card's constants and *DEPVAR.
struct PlyCard {
  CondensedCell cell;
  std::vector<double> props;
  int depvar = 0;
  std::string card;
};
// `stress_free_temperature`: phases that expand (the cell carries ΔT) and the card's 6th constant.
PlyCard ply_card(const std::filesystem::path& dir, int id, io::UmatBreaks breaks,
                 std::optional<double> stress_free_temperature = std::nullopt) {
  setenv("DUALCELL_CELL_DIR", dir.c_str(), 1);
  Scene s = parse_scene(testing::scene_text(1, 1, 2, 0.3), "test.toml");
  s.geometry.element = Element::p1;
  s.fibre = {30.0, 0.22};
  s.matrix = {1.0, 0.35};
  if (stress_free_temperature) {
    s.fibre.expands = s.matrix.expands = true;
    s.fibre.alpha = 5e-6;
    s.matrix.alpha = 6e-5;
  }
  s.load.boundary = Boundary::periodic;
  s.load.macro = Macro::full;
  s.interface.normal_strength = s.interface.tangential_strength = 0.01;
  const mesh::Mesh mesh = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(mesh, s);
  PlyCard out;
  out.cell = feti::condense(solver.setup());
  std::ostringstream text;
  write_cell_text(text, out.cell);
  std::ofstream(dir / io::umat_cell_file(id)) << text.str();
  Law law;
  law.constituents = with_isotropic_axes({30.0, 0.22, 1.0, 0.35, 0.28, 1.0});
  law.cell = out.cell;
  const std::uint64_t hash = text_hash_value(text.str());
  out.card = io::law_umat_cell(law, law::LawForm::cell, "PLY", id, hash, "law.h5", breaks, stress_free_temperature);
  out.depvar = 1 + out.cell.n_pairs + 3 + out.cell.n_rows() + out.cell.shear_rows;
  const double high = static_cast<double>(hash >> 32), low = static_cast<double>(hash & 0xffffffffULL);
  out.props = {3, static_cast<double>(id), high, low};
  if (breaks == io::UmatBreaks::between || stress_free_temperature)
    out.props.push_back(breaks == io::UmatBreaks::between ? 1 : 0);
  if (stress_free_temperature) out.props.push_back(*stress_free_temperature);
  return out;
}

// The whole ply (layout 3): a cell with the strain and the shears along the fibres gives all six
// components from the library's evaluation, in Abaqus's order (11, 22, 33, 12, 13, 23: x, y, z),
// along a path whose shear along the fibres breaks pairs; nothing is filled in by a rule of
// mixtures. A layout that does not match its cell is refused.
TEST(CellUmat, TheWholePlyGivesAllSixComponentsFromTheCell) {
  testing::ScratchDir dir;
  const PlyCard ply = ply_card(dir.path(), 7011, io::UmatBreaks::within);
  const CondensedCell& cell = ply.cell;
  ASSERT_EQ(cell.shear_rows, cell.n_pairs);
  ASSERT_NE(ply.card.find("*DEPVAR\n" + std::to_string(ply.depvar)), std::string::npos) << ply.card;
  ASSERT_NE(ply.card.find("CONSTANTS=4"), std::string::npos) << ply.card;
  const std::vector<double>& props = ply.props;
  const double high = props[2], low = props[3];
  const int depvar = ply.depvar;
  std::vector<double> statev(depvar, 0.0);

  CellEvaluator library(cell);
  CellHistory h = library.unloaded();
  Eigen::Matrix<double, 6, 1> direction;  // (ε11, ε22, ε33, γ12, γ13, γ23)
  direction << 0.2, -0.1, 0.3, 0.1, 1.0, 0.4;
  const int law_of[6] = {0, 1, 3, 2, 4, 5};  // the law's (xx, yy, xy, zz, xz, yz) index of each
  int broken_seen = 0;
  for (const double scale : {1e-4, 1e-3, 5e-3, 2e-2, 5e-3, 0.0}) {
    const Eigen::Matrix<double, 6, 1> e = scale * direction;
    const Call6 c = call6(props, e, statev);
    const CellResponse r = library.at(MacroState::strain(Eigen::Vector3d(e(0), e(1), e(3)))
                                          .hold(MacroState::zz, e(2))
                                          .hold_shear(Eigen::Vector2d(e(4), e(5))),
                                      h);
    ASSERT_TRUE(r.ok) << r.message;
    ASSERT_EQ(c.pnewdt, 1) << scale;
    Eigen::Matrix<double, 6, 1> sigma;
    sigma << r.stress, r.stress_zz, r.shear_z;
    Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
    D.topLeftCorner<3, 3>() = r.tangent;
    D.block<3, 1>(0, 3) = r.tangent_zz;
    D.block<1, 3>(3, 0) = r.tangent_zz.transpose();
    D(3, 3) = r.tangent_zz_zz;
    D.bottomRightCorner<2, 2>() = r.tangent_z;
    // The same QPs from the same warm starts: round-off apart.
    for (int i = 0; i < 6; ++i) {
      EXPECT_NEAR(c.stress(i), sigma(law_of[i]), 1e-12 * std::max(sigma.norm(), 1e-300)) << scale << " " << i;
      for (int j = 0; j < 6; ++j)
        EXPECT_NEAR(c.tangent(i, j), D(law_of[i], law_of[j]), 1e-12 * D.norm()) << scale << " " << i << j;
    }
    EXPECT_NEAR(c.energy, r.energy, 1e-12 * std::max(r.energy, 1e-300)) << scale;
    EXPECT_EQ(statev[0], r.broken) << scale;
    broken_seen = std::max(broken_seen, r.broken);
  }
  EXPECT_GT(broken_seen, 0) << "the path must reach past the first break";
  EXPECT_EQ(statev[0], broken_seen) << "bonds never heal";
  // A ply cell under a layout-2 card, and an in-plane cell under a layout-3 card: refused.
  std::vector<double> state(depvar, 0.0);
  EXPECT_EQ(call({2, 7011, 1, 1, 1, high, low}, Eigen::Vector3d(1e-4, 0, 0), state).pnewdt, 0.25);
}

// A whole ply's cell that carries a temperature change, its card with the stress-free temperature
// T0 = 20 (dualcell-export --stress-free-temperature, the 6th constant): at the code's temperature
// −80 the umat is the library at ΔT = −100, along a path from the cooled cell whose loads break
// pairs (the first call at zero strain: the free cell contracts, its stress is not zero); a card
// without the 6th constant is the library at ΔT = 0; the export refuses the constant for a cell
// without ΔT, and the umat a temperature change for such a cell.
TEST(CellUmat, TheWholePlyTakesTheTemperatureItIsGiven) {
  testing::ScratchDir dir;
  const PlyCard ply = ply_card(dir.path(), 7031, io::UmatBreaks::within, 20.0);
  const CondensedCell& cell = ply.cell;
  ASSERT_EQ(cell.thermal, 1);
  ASSERT_NE(ply.card.find("CONSTANTS=6"), std::string::npos) << ply.card;
  ASSERT_NE(ply.card.find(", 0.000000000000e+00, 2.000000000000e+01\n"), std::string::npos) << ply.card;
  std::vector<double> statev(ply.depvar, 0.0);
  CellEvaluator library(cell);
  CellHistory h = library.unloaded();
  Eigen::Matrix<double, 6, 1> direction;  // (ε11, ε22, ε33, γ12, γ13, γ23)
  direction << 0.3, -0.1, 0.2, 0.1, 0.4, 0.2;
  const int law_of[6] = {0, 1, 3, 2, 4, 5};
  int broken_seen = 0;
  for (const double scale : {0.0, 1e-3, 5e-3, 2e-2}) {
    const Eigen::Matrix<double, 6, 1> e = scale * direction;
    const Call6 c = call6(ply.props, e, statev, -80.0);
    ASSERT_EQ(c.pnewdt, 1) << scale;
    const CellResponse r = library.at(MacroState::strain(Eigen::Vector3d(e(0), e(1), e(3)))
                                          .hold(MacroState::zz, e(2))
                                          .hold_shear(Eigen::Vector2d(e(4), e(5)))
                                          .hold(MacroState::dT, -100.0),
                                      h);
    ASSERT_TRUE(r.ok) << r.message;
    const Eigen::Matrix<double, 6, 1> sigma = ply_stress(r);
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(c.stress(i), sigma(law_of[i]), 1e-12 * std::max(sigma.norm(), 1e-300)) << scale << " " << i;
    if (scale == 0) {
      EXPECT_GT(sigma.norm(), 0) << "held at zero strain, the cooled cell is stressed";
    }
    EXPECT_EQ(statev[0], r.broken) << scale;
    broken_seen = std::max(broken_seen, r.broken);
  }
  EXPECT_GT(broken_seen, 0) << "the path must reach past the first break";
  // Without the 6th constant: ΔT = 0, whatever the code's temperature.
  std::vector<double> cold(ply.depvar, 0.0);
  const std::vector<double> four(ply.props.begin(), ply.props.begin() + 4);
  const Call6 c = call6(four, 1e-3 * direction, cold, -80.0);
  CellHistory h0 = library.unloaded();
  const Eigen::Matrix<double, 6, 1> e = 1e-3 * direction;
  const CellResponse r = library.at(MacroState::strain(Eigen::Vector3d(e(0), e(1), e(3)))
                                        .hold(MacroState::zz, e(2))
                                        .hold_shear(Eigen::Vector2d(e(4), e(5))),
                                    h0);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_NEAR(c.stress(0), ply_stress(r)(0), 1e-12 * ply_stress(r).norm());
  // A cell without ΔT: the export refuses the constant, the umat a temperature change.
  testing::ScratchDir other;
  const PlyCard plain = ply_card(other.path(), 7032, io::UmatBreaks::within);
  Law law;
  law.constituents = with_isotropic_axes({30.0, 0.22, 1.0, 0.35, 0.28, 1.0});
  law.cell = plain.cell;
  try {
    io::law_umat_cell(law, law::LawForm::cell, "PLY", 7032, 1, "law.h5", io::UmatBreaks::within, 20.0);
    ADD_FAILURE() << "a cell without a temperature change took --stress-free-temperature";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("carries no temperature change"), std::string::npos) << error.what();
  }
  std::vector<double> props = plain.props, state(plain.depvar, 0.0);
  props.push_back(0);
  props.push_back(20);
  EXPECT_EQ(call6(props, 1e-3 * direction, state, -80.0).pnewdt, 0.25);
}

// Bonds breaking between increments (dualcell-export --breaks between, a 5th constant 1): within
// an increment the bonds of its start are held (the library's held evaluation), and the pairs the
// cascade at the strain would break are marked (state 2); the next increment at the same strain
// starts with them broken and is then the library's cascade from the intact cell, to round-off,
// and a third changes nothing. The umat's rounds are a structure's debond loop's.
TEST(CellUmat, BetweenIncrementsTheBondsAreHeldAndBreakAtTheNextIncrement) {
  testing::ScratchDir dir;
  const PlyCard ply = ply_card(dir.path(), 7012, io::UmatBreaks::between);
  ASSERT_NE(ply.card.find("CONSTANTS=5"), std::string::npos) << ply.card;
  const CondensedCell& cell = ply.cell;
  Eigen::Matrix<double, 6, 1> e;  // (ε11, ε22, ε33, γ12, γ13, γ23), past the bonds' strength
  e << 4e-3, -2e-3, 6e-3, 2e-3, 2e-2, 8e-3;
  const int law_of[6] = {0, 1, 3, 2, 4, 5};
  const auto library_at = [&](BondMode mode, CellHistory& h) {
    CellEvaluator library(cell);
    const CellResponse r = library.at(MacroState::strain(Eigen::Vector3d(e(0), e(1), e(3)))
                                          .hold(MacroState::zz, e(2))
                                          .hold_shear(Eigen::Vector2d(e(4), e(5))),
                                      h, mode);
    EXPECT_TRUE(r.ok) << r.message;
    return r;
  };
  CellEvaluator unloaded(cell);
  CellHistory held_h = unloaded.unloaded(), cascade_h = unloaded.unloaded();
  const CellResponse held = library_at(BondMode::held, held_h), cascade = library_at(BondMode::cascade, cascade_h);
  ASSERT_GT(cascade.broken, 0);
  std::vector<double> statev(ply.depvar, 0.0);
  const auto expect_equal = [&](const Call6& c, const CellResponse& r, const char* what) {
    const Eigen::Matrix<double, 6, 1> sigma = ply_stress(r);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(c.stress(i), sigma(law_of[i]), 1e-12 * sigma.norm()) << what << " " << i;
  };
  const Call6 first = call6(ply.props, e, statev);
  ASSERT_EQ(first.pnewdt, 1);
  expect_equal(first, held, "the first increment: the bonds held");
  EXPECT_EQ(statev[0], 0);
  int marked = 0;
  for (int p = 0; p < cell.n_pairs; ++p) {
    marked += statev[1 + p] == 2;
    EXPECT_EQ(statev[1 + p] == 2, cell.bonded[p] && !cascade_h.bonded[p]) << p;
  }
  EXPECT_EQ(marked, cascade.broken);
  const Call6 second = call6(ply.props, e, statev);
  expect_equal(second, cascade, "the second increment: the cascade's bonds");
  EXPECT_EQ(statev[0], cascade.broken);
  const std::vector<double> settled = statev;
  const Call6 third = call6(ply.props, e, statev);
  expect_equal(third, cascade, "the third increment");
  EXPECT_EQ(statev, settled) << "nothing more breaks";
  // Only a whole ply's card breaks between increments (layout 3).
  Law law;
  law.constituents = with_isotropic_axes({30.0, 0.22, 1.0, 0.35, 0.28, 1.0});
  law.cell = adhesive_cell();
  EXPECT_THROW(io::law_umat_cell(law, law::LawForm::cell, "CELL", 7013, 1, "law.h5", io::UmatBreaks::between),
               InputError);
}

// A cell file replaced after its card was written (another law exported under the same id,
// --force) is refused by the card that named the first one, not mixed with it; and a file that
// declares a million rows is refused by its count, where it once aborted the whole analysis with
// std::bad_alloc.
TEST(CellUmat, AReplacedOrOversizedCellFileIsRefusedNotMixed) {
  testing::ScratchDir dir;
  setenv("DUALCELL_CELL_DIR", dir.path().c_str(), 1);
  const CondensedCell cell = adhesive_cell();
  std::ostringstream out;
  write_cell_text(out, cell);
  const std::uint64_t hash = text_hash_value(out.str());
  std::string replaced = out.str();
  replaced.replace(replaced.find("volume "), 7, "volume  ");  // the same numbers, other bytes
  std::ofstream(dir / io::umat_cell_file(7003)) << replaced;
  const std::vector<double> props = {
      2, 7003, 1, 1, 1, static_cast<double>(hash >> 32), static_cast<double>(hash & 0xffffffffULL)};
  std::vector<double> state(1 + cell.n_pairs + 3 + cell.n_rows(), 0.0);
  EXPECT_EQ(call(props, Eigen::Vector3d(1e-3, 0, 0), state).pnewdt, 0.25);

  std::string huge = out.str();
  const auto at = huge.find("\nrows ") + 6;
  huge.replace(at, huge.find('\n', at) - at, "1000000");
  std::ofstream(dir / io::umat_cell_file(7004)) << huge;
  std::istringstream in(huge);
  std::string error;
  read_cell_text(in, error);
  EXPECT_EQ(error, "rows: 1000000 is not a count in [0, 3000]");
  std::vector<double> p = props;
  p[1] = 7004;
  EXPECT_EQ(call(p, Eigen::Vector3d(1e-3, 0, 0), state).pnewdt, 0.25);
}

// A cell file is judged by what it is and its size before a byte is read: a device (a link to
// /dev/zero once drove CalculiX past 4.5 GB in a minute) or a directory gets its own line, and a
// file larger than the largest cell the limits allow (a sparse 8 GiB file here) is refused from
// its size, at once.
TEST(CellUmat, ACellFileThatIsNoRegularFileOrTooLargeIsRefusedBeforeItIsRead) {
  testing::ScratchDir dir;
  setenv("DUALCELL_CELL_DIR", dir.path().c_str(), 1);
  std::filesystem::create_symlink("/dev/zero", dir / io::umat_cell_file(7021));
  std::filesystem::create_directory(dir / io::umat_cell_file(7022));
  std::ofstream(dir / io::umat_cell_file(7023)).close();
  std::filesystem::resize_file(dir / io::umat_cell_file(7023), std::uintmax_t{8} << 30);
  // The bound: the text of a cell at max_cell_rows with every number at its longest, about 900 MB.
  EXPECT_GT(max_cell_text_bytes(), std::uintmax_t{800} << 20);
  EXPECT_LT(max_cell_text_bytes(), std::uintmax_t{1} << 30);
  const std::pair<int, const char*> cases[] = {
      {7021, "is not a regular file"}, {7022, "is not a regular file"}, {7023, "more than the largest cell"}};
  for (const auto& [id, expected] : cases) {
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(dualcell_cell_statev(id), -1) << id;
    const std::string told = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(told.find(expected), std::string::npos) << id << ": " << told;
    EXPECT_EQ(testing::occurrences(told, "\n"), 1u) << told;
  }
}

}  // namespace
}  // namespace dualcell::law
