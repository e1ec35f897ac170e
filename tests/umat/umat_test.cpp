// The user material for other FE codes (src/umat/dualcell_umat.c) with the constants
// dualcell-export writes (io::umat_constants) against the library's own evaluation of the law
// (law::evaluate) on random strains, and its fuse: once a point's stress leaves the onset
// surface it takes the law past the fuse, and a fused point stays fused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <random>

#include "io/law_export.hpp"
#include "umat/umat_signature.hpp"

namespace dualcell::law {
namespace {

// The formats are io's, the 3D material the law's.
using io::law_calculix;
using io::law_csv;
using io::law_json;
using io::law_umat;
using io::umat_constants;

// A law as the fit makes them: SPD C_c, compression struts, a softer law past the fuse, and an
// onset surface of a few facets; realistic constituents for the out-of-plane constants.
Law test_law() {
  Law law;
  law.constituents = with_isotropic_axes({72.0, 0.22, 3.5, 0.35, 0.38, 1.0});
  law.cone.ok = true;
  law.cone.law.C_c << 10.3, 4.3, 0.1, 4.3, 10.1, -0.05, 0.1, -0.05, 2.2;
  law.cone.law.q = {Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, -1, 0),
                    Eigen::Vector3d(-0.5, -0.5, 1 / std::sqrt(2.0))};
  law.cone.law.beta = {3.0, 2.5, 1.0};
  law.cone_after_fuse.ok = true;
  law.cone_after_fuse.law.C_c = 0.3 * law.cone.law.C_c;
  law.cone_after_fuse.law.q = law.cone.law.q;
  law.cone_after_fuse.law.beta = {9.0, 8.0, 2.0};
  law.onset.linear = true;
  law.onset.facets.resize(3, 3);
  law.onset.facets << 100, 0, 0, 0, 100, 0, 20, 20, 60;  // σxx ≤ 0.01, σyy ≤ 0.01, a mixed one
  return law;
}

struct Call {
  Eigen::Vector3d stress;  // (σ11, σ22, σ12)
  Eigen::Matrix3d tangent;
  double energy, state;
};

// One call of the umat at the plane strain (ε11, ε22, γ12), split into a start and an increment
// as a code does; the state variable before the call is `state`.
Call call(const std::vector<double>& props, const Eigen::Vector3d& e, double state) {
  double stress[6] = {}, statev[1] = {state}, ddsdde[36], sse = 0, spd = 0, scd = 0, rpl = 0, ddsddt[6], drplde[6];
  double drpldt = 0, time[2] = {0, 0}, dtime = 1, temp = 0, dtemp = 0, predef = 0, dpred = 0, coords[3] = {};
  double drot[9] = {}, pnewdt = 1, celent = 1, dfgrd[9] = {};
  const double stran[6] = {0.3 * e(0), 0.3 * e(1), 0, 0.3 * e(2), 0, 0};
  const double dstran[6] = {0.7 * e(0), 0.7 * e(1), 0, 0.7 * e(2), 0, 0};
  const int ndi = 3, nshr = 3, ntens = 6, nstatv = 1, nprops = static_cast<int>(props.size()), one = 1;
  umat_(stress, statev, ddsdde, &sse, &spd, &scd, &rpl, ddsddt, drplde, &drpldt, stran, dstran, time, &dtime, &temp,
        &dtemp, &predef, &dpred, "ABAQUS_TEST", &ndi, &nshr, &ntens, &nstatv, props.data(), &nprops, coords, drot,
        &pnewdt, &celent, dfgrd, dfgrd, &one, &one, &one, &one, &one, &one, 11);
  EXPECT_EQ(pnewdt, 1.0) << "the umat refused its constants";
  Call c;
  const int in_plane[3] = {0, 1, 3};
  for (int i = 0; i < 3; ++i) {
    c.stress(i) = stress[in_plane[i]];
    for (int j = 0; j < 3; ++j) c.tangent(i, j) = ddsdde[in_plane[i] + 6 * in_plane[j]];
  }
  c.energy = sse;
  c.state = statev[0];
  return c;
}

// Random strains of both signs over every cone: stress, tangent and energy equal the library's
// to 1e-13 relative (the same arithmetic in another order); below the onset surface the point
// stays bonded, above it takes the law past the fuse, and a fused point keeps that law.
TEST(Umat, EqualsTheLibraryLawAndItsFuseOnRandomStrains) {
  const Law law = test_law();
  const std::vector<double> props = umat_constants(law, "test");
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1, 1);
  int bonded = 0, fused = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d e = 2e-3 * Eigen::Vector3d(uniform(random), uniform(random), uniform(random));
    const ConeState b = evaluate(law.cone.law, e);
    const bool leaves = onset_measure(law.onset, b.stress) >= 1;
    const ConeState expected = leaves ? evaluate(law.cone_after_fuse.law, e) : b;
    const Call c = call(props, e, 0);
    EXPECT_EQ(c.state, leaves ? 1.0 : 0.0);
    EXPECT_LE((c.stress - expected.stress).norm(), 1e-13 * expected.stress.norm());
    EXPECT_LE((c.tangent - expected.tangent).norm(), 1e-13 * expected.tangent.norm());
    EXPECT_NEAR(c.energy, expected.energy, 1e-13 * expected.energy);
    // Fused before: the law past the fuse whatever the stress.
    const Call after = call(props, e, 1);
    const ConeState a = evaluate(law.cone_after_fuse.law, e);
    EXPECT_EQ(after.state, 1.0);
    EXPECT_LE((after.stress - a.stress).norm(), 1e-13 * a.stress.norm());
    (leaves ? fused : bonded) += 1;
  }
  EXPECT_GT(bonded, 100);  // both sides of the onset surface were visited
  EXPECT_GT(fused, 100);
}

// A law without a law past the fuse writes K_a = F = 0: points never fuse.
TEST(Umat, WithoutALawPastTheFusePointsStayBonded) {
  Law law = test_law();
  law.cone_after_fuse.ok = false;
  const std::vector<double> props = umat_constants(law, "test");
  EXPECT_EQ(props[2], 0.0);
  EXPECT_EQ(props[3], 0.0);
  const Eigen::Vector3d e(5e-3, 0, 0);  // far outside the onset surface
  const Call c = call(props, e, 0);
  EXPECT_EQ(c.state, 0.0);
  EXPECT_LE((c.stress - evaluate(law.cone.law, e).stress).norm(), 1e-13 * c.stress.norm());
}

// CalculiX reads CONSTANTS/8 + 1 lines of a *USER MATERIAL: a card of 32 planes has 7 + 9 + 128
// = 144 constants, a multiple of 8, and is padded with one trailing 0 so that its last line is
// complete for both CalculiX and Abaqus; the umat reads the same law from the padded constants.
TEST(Umat, ACardWhoseConstantsFillTheirLinesIsPadded) {
  Law law = test_law();
  law.cone_after_fuse.ok = false;
  law.cone.law.q.assign(32, Eigen::Vector3d(-1, 0, 0));
  law.cone.law.beta.assign(32, 0.1);
  ASSERT_EQ(umat_constants(law, "test").size(), 144u);
  const std::string card = law_umat(law, "PADDED", "test");
  EXPECT_NE(card.find("CONSTANTS=145"), std::string::npos) << card;
  const std::string values = card.substr(card.find("CONSTANTS=145") + 14);
  EXPECT_EQ(std::count(values.begin(), values.begin() + values.find("*DEPVAR"), '\n'), 19);
  std::vector<double> props = umat_constants(law, "test");
  props.push_back(0.0);
  const Eigen::Vector3d e(1e-3, -2e-3, 5e-4);
  EXPECT_LE((call(props, e, 0).stress - evaluate(law.cone.law, e).stress).norm(), 1e-13 * e.norm() * 20);
}

}  // namespace
}  // namespace dualcell::law
