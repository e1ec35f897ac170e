// dualcell-export: the 3D constants reproduce the plane-strain law (algebra, then the real
// CalculiX solver on a small plane-strain model), JSON read by Python, CSV with one row per
// direction, and refusals of bad law files and inadmissible laws that leave no output.
#include "io/law_export.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/exit_codes.hpp"
#include "io/hdf5.hpp"
#include "io/law_file.hpp"
#include "law/synthetic_law.hpp"
#include "test_util.hpp"

namespace dualcell::law {
namespace {

// The formats are io's, the 3D material the law's.
using io::law_calculix;
using io::law_csv;
using io::law_json;
using io::law_umat;
using io::umat_constants;

using testing::bin;
using testing::run_command;

// The required agreement of the apparent modulus in CalculiX (docs/guide/export.md).
constexpr double ccx_tolerance = 0.005;

// The plane-strain compliance of a 3D one: ε33 = 0 ⇒ σ33 = −(S31 σ11 + S32 σ22 + S34 σ12)/S33,
// condensed in Voigt order (11, 22, 33, 12, 13, 23), in-plane rows (11, 22, 12).
Eigen::Matrix3d condense(const SolidMaterial::Matrix6d& S) {
  const int in_plane[3] = {0, 1, 3};
  Eigen::Matrix3d S_ps;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      S_ps(i, j) = S(in_plane[i], in_plane[j]) - S(in_plane[i], 2) * S(2, in_plane[j]) / S(2, 2);
  return S_ps;
}

Eigen::Matrix3d coupled_compliance() {
  Eigen::Matrix3d S = testing::plane_strain_compliance(6.0, 8.0, 0.4, 2.5);
  S(0, 2) = S(2, 0) = 0.02;
  S(1, 2) = S(2, 1) = -0.015;
  return S;
}

TEST(Export, SolidMaterialReproducesThePlaneStrainCompliance) {
  const Law law = testing::synthetic_law();
  for (const Eigen::Matrix3d& S_ps : {law.tension.S, law.compression.S, coupled_compliance()}) {
    const SolidMaterial m = solid_material(S_ps, law, "law.h5", "S");
    EXPECT_LT((condense(m.S) - S_ps).norm(), 1e-14 * S_ps.norm());
    EXPECT_LT((m.S * m.C - SolidMaterial::Matrix6d::Identity()).norm(), 1e-12);
  }
  // Out of plane by the rule of mixtures, computed here from the constituents directly.
  const double Vf = law.constituents.fibre_volume_fraction;
  const double E3 = Vf * 72 + (1 - Vf) * 3.5, nu31 = Vf * 0.22 + (1 - Vf) * 0.35;
  const double G = 1 / (Vf / (72 / (2 * 1.22)) + (1 - Vf) / (3.5 / (2 * 1.35)));
  const SolidMaterial m = solid_material(law.tension.S, law, "law.h5", "S_tension");
  ASSERT_TRUE(m.orthotropic);
  const auto& k = m.constants;
  EXPECT_NEAR(k.E3, E3, 1e-12 * E3);
  EXPECT_NEAR(k.G13, G, 1e-12 * G);
  EXPECT_NEAR(k.G23, G, 1e-12 * G);
  // ν31 = ν13 E3/E1 (reciprocity S13 = S31).
  EXPECT_NEAR(k.nu13 * E3 / k.E1, nu31, 1e-12);
  EXPECT_NEAR(k.nu23 * E3 / k.E2, nu31, 1e-12);
  EXPECT_NEAR(k.G12, 2.5, 1e-12);
  // The engineering constants rebuild the 3D compliance.
  SolidMaterial::Matrix6d S = SolidMaterial::Matrix6d::Zero();
  S.diagonal() << 1 / k.E1, 1 / k.E2, 1 / k.E3, 1 / k.G12, 1 / k.G13, 1 / k.G23;
  S(0, 1) = S(1, 0) = -k.nu12 / k.E1;
  S(0, 2) = S(2, 0) = -k.nu13 / k.E1;
  S(1, 2) = S(2, 1) = -k.nu23 / k.E2;
  EXPECT_LT((S - m.S).norm(), 1e-14 * S.norm());
  // Coupling decides the card type.
  EXPECT_FALSE(solid_material(coupled_compliance(), law, "law.h5", "S").orthotropic);
}

std::string refusal(const Eigen::Matrix3d& S, const Law& law) {
  try {
    solid_material(S, law, "law.h5", "S_tension");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << S;
  return "";
}

// A law whose exact law carries the whole ply takes its out-of-plane constants from the cell (the
// ply's constants, /law/ply: E3 = E1, ν31 = ν12, ν32 = ν13, G13 = G12, G23 = G13, the ply's axis 1
// being z), not from the rule of mixtures: bonded with adhesion (either sign), the contact state
// of each sign without. Plane strain still reproduces the fitted compliance.
TEST(Export, AWholePlysLawTakesItsOutOfPlaneConstantsFromTheCell) {
  Law law = testing::synthetic_law();
  const auto row = [](PlyState state, int sign, double E1, double nu12, double nu13, double G12, double G13) {
    PlyConstants c;
    c.state = state, c.sign = sign, c.E1 = E1, c.nu12 = nu12, c.nu13 = nu13, c.G12 = G12, c.G13 = G13;
    return c;
  };
  law.ply.rows = {row(PlyState::contact, 1, 29.879, 0.29244, 0.29, 0.57251, 0.6),
                  row(PlyState::contact, -1, 29.861, 0.35, 0.34, 0.57251, 0.6)};
  for (const int sign : {1, -1}) {
    const PlyConstants& c = law.ply.rows[sign > 0 ? 0 : 1];
    const Eigen::Matrix3d& S_ps = sign > 0 ? law.tension.S : law.compression.S;
    const SolidMaterial m = solid_material(S_ps, law, "law.h5", "S", sign);
    EXPECT_LT((condense(m.S) - S_ps).norm(), 1e-14 * S_ps.norm());
    EXPECT_NEAR(m.S(2, 2), 1 / c.E1, 1e-15);
    EXPECT_NEAR(m.S(0, 2), -c.nu12 / c.E1, 1e-15);
    EXPECT_NEAR(m.S(1, 2), -c.nu13 / c.E1, 1e-15);
    EXPECT_NEAR(m.S(4, 4), 1 / c.G12, 1e-13);
    EXPECT_NEAR(m.S(5, 5), 1 / c.G13, 1e-13);
  }
  // Bonded rows win over any other state, whatever the sign.
  law.ply.rows.push_back(row(PlyState::bonded, 1, 30.0, 0.3, 0.31, 2.7, 2.8));
  EXPECT_EQ(out_of_plane(law, -1).E3, 30.0);
  EXPECT_EQ(out_of_plane(law, -1).G23, 2.8);
  EXPECT_TRUE(out_of_plane(law).from_cell);
  const std::string card = law_umat(law, "PLY", "law.h5");
  EXPECT_NE(card.find("E33, G13, G23 (the cell's, /law/ply)"), std::string::npos) << card;
  law.ply.rows.clear();
  EXPECT_FALSE(out_of_plane(law).from_cell);
}

TEST(Export, InadmissibleLawsAreRefused) {
  const Law law = testing::synthetic_law();
  Eigen::Matrix3d S = law.tension.S;
  S(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal(S, law).find("law.h5: /law/S_tension: entry (xy,xy) is nan: the sweep does not determine it"),
            std::string::npos);
  S = law.tension.S;
  S(0, 1) *= 1.01;
  EXPECT_NE(refusal(S, law).find("not symmetric"), std::string::npos);
  // ν so large that S_ps is indefinite: S12² > S11 S22.
  S = testing::plane_strain_compliance(6.0, 8.0, 1.0, 2.5);
  EXPECT_NE(refusal(S, law).find("law.h5: /law/S_tension: not positive definite"), std::string::npos);
  S = law.tension.S;
  S(2, 2) = -S(2, 2);
  EXPECT_NE(refusal(S, law).find("not positive definite"), std::string::npos);
  Law no_constituents = law;
  no_constituents.constituents.fibre_E = 0;
  EXPECT_NE(refusal(law.tension.S, no_constituents).find("law.h5: /law: attribute fibre_E = 0: out of range > 0"),
            std::string::npos);
  no_constituents = law;
  no_constituents.constituents.fibre_volume_fraction = 1.2;
  EXPECT_NE(refusal(law.tension.S, no_constituents).find("fibre_volume_fraction = 1.2"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// CalculiX

// Displacements (ux, uy) of the nodes of the first *NODE PRINT block of a CalculiX .dat file.
std::map<int, Eigen::Vector2d> read_dat_displacements(const std::filesystem::path& dat) {
  std::ifstream in(dat);
  std::map<int, Eigen::Vector2d> u;
  std::string line;
  bool in_block = false;
  while (std::getline(in, line)) {
    if (line.find("displacements") != std::string::npos) {
      in_block = true;
      continue;
    }
    if (!in_block) continue;
    std::istringstream row(line);
    int node = 0;
    double ux = 0, uy = 0, uz = 0;
    if (row >> node >> ux >> uy >> uz) {
      u[node] = {ux, uy};
    } else if (!u.empty()) {
      break;
    }
  }
  return u;
}

// Uniaxial stress s along n = (cos θ, sin θ) in CalculiX: a unit square of 2×2 plane-strain
// CPE4 elements (thickness 0.1) of `material`, taken from cards.inp in `dir` by *INCLUDE, its
// edges along n and t = (−sin θ, cos θ), pressures −s on the two edges normal to n. Supports are
// the minimum that removes rigid motion (corner 1 fixed; at corner 7, x = t, a rotation ω moves
// it by −ω n, so the component of u there most nearly along n is fixed), so that any
// homogeneous strain, shear included, is free to appear; bilinear elements hold a homogeneous
// field exactly, so three corners give (ε_nn, ε_tt, γ_nt). Off the axes (θ ≠ 0, 90°) the stress
// has a shear part σxy = s cos θ sin θ, so G12 is checked too.
//
//   7 --- 8 --- 9        t
//   |  3  |  4  |        ^
//   4 --- 5 --- 6        |
//   |  1  |  2  |        +--> n
//   1 --- 2 --- 3
Eigen::Vector3d ccx_strain(const testing::ScratchDir& dir, const std::string& material, double s, double theta_deg) {
  const double theta = theta_deg * std::numbers::pi / 180;
  const Eigen::Vector2d n(std::cos(theta), std::sin(theta)), t(-std::sin(theta), std::cos(theta));
  std::string job =
      "** dualcell-export test: uniaxial stress on a plane-strain square\n"
      "*INCLUDE, INPUT=cards.inp\n"
      "*NODE, NSET=NALL\n";
  for (int node = 0; node < 9; ++node) {
    const Eigen::Vector2d x = 0.5 * (node % 3) * n + 0.5 * (node / 3) * t;
    char line[96];
    std::snprintf(line, sizeof line, "%d, %.15g, %.15g\n", node + 1, x(0), x(1));
    job += line;
  }
  // CPE4 faces: P1 = nodes 1–2, P2 = 2–3, P3 = 3–4, P4 = 4–1; here P2 faces +n, P4 faces −n.
  const std::string pressure = std::to_string(-s);
  const std::string rotation_dof = std::abs(n(0)) >= std::abs(n(1)) ? "1" : "2";
  job +=
      "*ELEMENT, TYPE=CPE4, ELSET=EALL\n"
      "1, 1, 2, 5, 4\n2, 2, 3, 6, 5\n3, 4, 5, 8, 7\n4, 5, 6, 9, 8\n"
      "*NSET, NSET=CORNERS\n1, 3, 7, 9\n"
      "*SOLID SECTION, ELSET=EALL, MATERIAL=" +
      material +
      "\n0.1\n"
      "*BOUNDARY\n1, 1, 2\n7, " +
      rotation_dof + ", " + rotation_dof +
      "\n"
      "*STEP\n*STATIC\n*DLOAD\n"
      "2, P2, " +
      pressure + "\n4, P2, " + pressure + "\n1, P4, " + pressure + "\n3, P4, " + pressure +
      "\n"
      "*NODE PRINT, NSET=CORNERS\nU\n*END STEP\n";
  dir.write("square.inp", job);
  std::filesystem::remove(dir / "square.dat");
  // ccx writes its files next to the input, in the working folder.
  const auto r = run_command("cd " + dir.path().string() + " && OMP_NUM_THREADS=1 ccx -i square");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto u = read_dat_displacements(dir / "square.dat");
  EXPECT_EQ(u.size(), 4u) << r.output;
  if (u.size() != 4) return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  const Eigen::Vector2d along_n = u.at(3) - u.at(1), along_t = u.at(7) - u.at(1);
  return {n.dot(along_n), t.dot(along_t), t.dot(along_n) + n.dot(along_t)};
}

// Loads the square along θ = 0, 30, 90° and compares CalculiX's strains with ε = S_ps σ in the
// (n, t) frame: the apparent plane-strain modulus s/ε_nn (the law's E(θ)) and the whole strain.
void expect_ccx_reproduces(const testing::ScratchDir& dir, const std::string& material, const Eigen::Matrix3d& S_ps,
                           double sign) {
  for (const double theta_deg : {0.0, 30.0, 90.0}) {
    const double s = sign * 0.01, theta = theta_deg * std::numbers::pi / 180;
    const Eigen::Vector2d n(std::cos(theta), std::sin(theta)), t(-std::sin(theta), std::cos(theta));
    // σ = s n⊗n as (σxx, σyy, σxy); ε = S_ps σ with engineering shear, as a tensor E.
    const Eigen::Vector3d e = S_ps * Eigen::Vector3d(s * n(0) * n(0), s * n(1) * n(1), s * n(0) * n(1));
    Eigen::Matrix2d E;
    E << e(0), e(2) / 2, e(2) / 2, e(1);
    const Eigen::Vector3d expected(n.dot(E * n), t.dot(E * t), 2 * n.dot(E * t));
    const Eigen::Vector3d strain = ccx_strain(dir, material, s, theta_deg);
    const double modulus = s / strain(0), fitted = s / expected(0);
    const double modulus_error = std::abs(modulus / fitted - 1);
    const double strain_error = (strain - expected).cwiseAbs().maxCoeff() / expected.cwiseAbs().maxCoeff();
    std::printf("[ ccx      ] %-23s at %2.0f deg: E = %.7g, fitted %.7g, modulus error %.1e, strain error %.1e\n",
                material.c_str(), theta_deg, modulus, fitted, modulus_error, strain_error);
    EXPECT_LT(modulus_error, ccx_tolerance) << material << " at " << theta_deg;
    EXPECT_LT(strain_error, ccx_tolerance)
        << material << " at " << theta_deg << ": " << strain.transpose() << " vs " << expected.transpose();
  }
}

Law write_law_and_export(const testing::ScratchDir& dir, const Law& law) {
  io::write_law(dir / "law.h5", law);
  const auto r = run_command(bin("dualcell-export") + " --law " + (dir / "law.h5").string() +
                             " --format calculix --name GLASS_EPOXY --out " + (dir / "cards.inp").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("GLASS_EPOXY_TENSION and GLASS_EPOXY_COMPRESSION"), std::string::npos) << r.output;
  return law;
}

TEST(Export, CalculixReproducesTheFittedModuliInPlaneStrain) {
  testing::ScratchDir dir;
  const Law law = write_law_and_export(dir, testing::synthetic_law());
  std::ifstream in(dir / "cards.inp");
  const std::string cards((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(cards.find("*MATERIAL, NAME=GLASS_EPOXY_TENSION\n"), std::string::npos);
  EXPECT_NE(cards.find("*MATERIAL, NAME=GLASS_EPOXY_COMPRESSION\n"), std::string::npos);
  EXPECT_EQ(cards.find("TYPE=ANISO"), std::string::npos);
  // The test is sensitive to the plane-strain conversion: leaving out S13²/S33 would change the
  // x modulus by this much, several times the tolerance.
  const SolidMaterial m = solid_material(law.tension.S, law, "law.h5", "S_tension");
  EXPECT_GT(m.S(0, 2) * m.S(0, 2) / m.S(2, 2) / law.tension.S(0, 0), 4 * ccx_tolerance);
  expect_ccx_reproduces(dir, "GLASS_EPOXY_TENSION", law.tension.S, +1);
  expect_ccx_reproduces(dir, "GLASS_EPOXY_COMPRESSION", law.compression.S, -1);
}

TEST(Export, CalculixAnisoCardsCarryNormalShearCoupling) {
  testing::ScratchDir dir;
  Law law = testing::synthetic_law();
  law.tension.S = coupled_compliance();
  write_law_and_export(dir, law);
  std::ifstream in(dir / "cards.inp");
  const std::string cards((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(cards.find("*MATERIAL, NAME=GLASS_EPOXY_TENSION\n** normal-shear coupling"), std::string::npos);
  EXPECT_NE(cards.find("*ELASTIC, TYPE=ANISO\n"), std::string::npos);
  expect_ccx_reproduces(dir, "GLASS_EPOXY_TENSION", law.tension.S, +1);
  expect_ccx_reproduces(dir, "GLASS_EPOXY_COMPRESSION", law.compression.S, -1);
}

// ---------------------------------------------------------------------------------------------
// JSON, CSV and the command line

std::string export_command(const testing::ScratchDir& dir, const std::string& law_file, const std::string& format,
                           const std::string& out) {
  return bin("dualcell-export") + " --law " + (dir / law_file).string() + " --format " + format + " --out " +
         (dir / out).string();
}

TEST(Export, JsonIsReadByPythonWithEveryObject) {
  testing::ScratchDir dir;
  const Law law = testing::synthetic_law();
  io::write_law(dir / "law.h5", law);
  const auto r = run_command(export_command(dir, "law.h5", "json", "law.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Debian's python3: strict JSON (no NaN literal) that json.load accepts.
  const auto parse =
      run_command("/usr/bin/python3 -c 'import json,sys; json.load(open(sys.argv[1]))' " + (dir / "law.json").string());
  EXPECT_EQ(parse.exit_code, 0) << parse.output;
  const std::string script =
      "import json, math, sys\n"
      "def strict(c): raise ValueError('non-standard constant ' + c)\n"
      "d = json.load(open(sys.argv[1]), parse_constant=strict)\n"
      "assert d['format'] == 'dualcell law 4'\n"
      "assert d['cone']['q'] == [[0.6, 0.8, 0.0], [0.0, 0.0, 1.0]] and d['cone']['beta'] == [2.5, 0.75]\n"
      "assert d['cone']['ok'] == 1 and d['cone']['form'] == 'compression struts'\n"
      "assert d['cone']['one_plane_residual'] == 0.05 and d['cone_after_fuse']['struts_residual'] is None\n"
      "assert d['cone']['C_c'][0][1] == 2.9 and d['cone']['direction_residual'][2] is None\n"
      "assert d['cone_after_fuse']['ok'] == 0 and d['cone_after_fuse']['message'] == 'fewer than 3 points'\n"
      "o = d['onset']\n"
      "assert o['linear'] == 1 and o['facets'][1] == [-2.0, 4.0, 0.5] and o['pair'] == [4, 7, 7]\n"
      "assert o['tangential'] == [0, 0, 1] and o['path_stress'][1] == [-1.0, 0.0, 0.0]\n"
      "assert o['onset'] == [0.05, 0.5] and o['sweep_onset'] == [0.05, None]\n"
      "assert d['direction_deg'] == [0, 30, 60, 90]\n"
      "assert d['E_tension'][1] == 7.0 and d['n_tension'] == [5, 6, 7, 8]\n"
      "assert d['fuse_stress'][2] is None and d['fuse_stress'][0] == 0.0586\n"
      "assert d['S_tension'][0][1] == -0.4 / 6.0 and d['S_tension_se'][2][2] is None\n"
      "assert d['S_tension_direction_residual'][2] is None and d['S_compression_rank'] == 5\n"
      "assert d['cone_normal'] == [0.8, 0.6, 0.0] and d['cone_wise_linear'] == 1\n"
      "assert d['scene'].startswith('[geometry]') and '\"quoted\"' in d['scene']\n"
      "assert d['stress_state'] == 'plane strain' and 'engineering shear' in d['shear_convention']\n"
      "assert abs(d['fibre_volume_fraction'] - math.pi * 0.09) < 1e-15\n"
      "assert d['fibre_E_L'] == 72 and d['matrix_nu_LT'] == 0.35 and d['fibre_G_LT'] == 72 / (2 * 1.22)\n"
      "print(len(d))\n";
  const auto check =
      run_command("/usr/bin/python3 " + dir.write("check.py", script).string() + " " + (dir / "law.json").string());
  ASSERT_EQ(check.exit_code, 0) << check.output;
  // 20 per-direction columns, 7 objects per fit, 4 cone objects, 2 cone-wise fits, the onset
  // surface, 5 constituents and the cell size, the 6 along the fibres' axis, format and 5
  // provenance texts, 3 /law texts, and the notes that say why there is no exact law and no small
  // cell (this law has neither).
  EXPECT_EQ(check.output, "64\n");
}

TEST(Export, CsvHasAHeaderAndOneRowPerDirection) {
  testing::ScratchDir dir;
  io::write_law(dir / "law.h5", testing::synthetic_law());
  const auto r = run_command(export_command(dir, "law.h5", "csv", "law.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir / "law.csv");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u + 1u);
  EXPECT_EQ(lines[0].rfind("direction_deg,E_tension,E_tension_se,", 0), 0u) << lines[0];
  // 20 per-direction columns, the residuals of S_tension, S_compression and the two cone fits.
  for (const auto& line : lines) EXPECT_EQ(std::count(line.begin(), line.end(), ','), 23) << line;
  EXPECT_EQ(lines[1].rfind("0,6,0.01,", 0), 0u) << lines[1];
  EXPECT_NE(lines[4].find(",nan,"), std::string::npos) << lines[4];
  // The same file through Python's csv reader.
  const auto check = run_command(
      "/usr/bin/python3 -c 'import csv,sys; r = list(csv.DictReader(open(sys.argv[1]))); "
      "print(len(r), r[3][\"fuse_stress\"], float(r[1][\"E_compression\"]), r[1][\"cone_direction_residual\"], "
      "r[0][\"cone_after_fuse_direction_residual\"])' " +
      (dir / "law.csv").string());
  EXPECT_EQ(check.output, "4 nan 9.5 0.025000000000000001 nan\n");
}

// One line on stderr, exit code 1 and no output file (nor temporary) for every bad input.
void expect_refused(const testing::ScratchDir& dir, const std::string& law_file, const std::string& format,
                    const std::string& expected, const std::string& extra = "") {
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    ASSERT_EQ(e.path().filename().string().find("out."), std::string::npos) << "left over: " << e.path();
  const auto r = run_command(export_command(dir, law_file, format, "out." + format) + extra);
  EXPECT_EQ(r.exit_code, exit_input_error) << r.output;
  EXPECT_EQ(r.output.rfind("dualcell-export: error: ", 0), 0u) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    EXPECT_EQ(e.path().filename().string().find("out."), std::string::npos) << "left behind: " << e.path();
}

TEST(Export, BadLawFilesAreRefusedWithOneLineAndNoOutput) {
  testing::ScratchDir dir;
  Law law = testing::synthetic_law();
  io::write_law(dir / "law.h5", law);
  std::filesystem::copy_file(dir / "law.h5", dir / "cut.h5");
  std::filesystem::resize_file(dir / "cut.h5", std::filesystem::file_size(dir / "law.h5") / 2);
  dir.write("text.h5", "not hdf5");
  std::filesystem::copy_file(dir / "law.h5", dir / "incomplete.h5");
  io::File::open_write(dir / "incomplete.h5").remove("/law/E_compression");
  for (const std::string format : {"json", "csv", "calculix"}) {
    expect_refused(dir, "cut.h5", format, "cut.h5: ");
    expect_refused(dir, "cut.h5", format, "truncated or corrupt");
    expect_refused(dir, "text.h5", format, "text.h5: not an HDF5 file");
    expect_refused(dir, "incomplete.h5", format, "incomplete.h5: /law/E_compression: missing dataset");
    expect_refused(dir, "absent.h5", format, "absent.h5: file not found");
  }
  // Readable, but no admissible 3D material: CalculiX only.
  law.compression.S(2, 2) = std::numeric_limits<double>::quiet_NaN();
  io::write_law(dir / "shear-unknown.h5", law);
  expect_refused(dir, "shear-unknown.h5", "calculix", "/law/S_compression: entry (xy,xy) is nan");
  EXPECT_EQ(run_command(export_command(dir, "shear-unknown.h5", "json", "law.json")).exit_code, 0);
  law = testing::synthetic_law();
  law.tension.S = testing::plane_strain_compliance(6.0, 8.0, 1.5, 2.5);
  io::write_law(dir / "indefinite.h5", law);
  expect_refused(dir, "indefinite.h5", "calculix", "/law/S_tension: not positive definite");
  expect_refused(dir, "law.h5", "calculix", "--name 1ABC: expected a letter", " --name 1ABC");
  // A folder that does not exist.
  const auto r = run_command(bin("dualcell-export") + " --law " + (dir / "law.h5").string() + " --format csv --out " +
                             (dir / "no/such/law.csv").string());
  EXPECT_EQ(r.exit_code, exit_input_error) << r.output;
  EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
}

TEST(Export, HelpAndCommandLineErrors) {
  const auto help = run_command(bin("dualcell-export") + " --help");
  EXPECT_EQ(help.exit_code, 0);
  for (const char* text : {"--law", "--format", "--out", "--name", "json", "csv", "calculix", "DUALCELL"})
    EXPECT_NE(help.output.find(text), std::string::npos) << text << "\n" << help.output;
  testing::ScratchDir dir;
  io::write_law(dir / "law.h5", testing::synthetic_law());
  const auto r = run_command(export_command(dir, "law.h5", "xml", "law.xml"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("xml"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "law.xml"));
  EXPECT_NE(run_command(bin("dualcell-export") + " --format json").exit_code, 0);
}

}  // namespace
}  // namespace dualcell::law
