#include "law/solid.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"

namespace dualcell::law {

void check_constituents(const Law& law, const std::string& file) {
  const std::string where = file + ": /law: ";
  auto need = [&](bool ok, const char* name, double value, const char* range) {
    if (!ok)
      throw InputError(where + "attribute " + name + " = " + formatted("%g", value) + ": out of range " + range +
                       " (the constituents give the out-of-plane constants of the 3D material)");
  };
  need(std::isfinite(law.constituents.fibre_E) && law.constituents.fibre_E > 0, "fibre_E", law.constituents.fibre_E,
       "> 0");
  need(std::isfinite(law.constituents.matrix_E) && law.constituents.matrix_E > 0, "matrix_E", law.constituents.matrix_E,
       "> 0");
  // Each phase's compliance positive definite: an isotropic phase (its axial constants those of
  // its E and ν) has −1 < ν < 0.5; a transversely isotropic one −1 < ν < 1, E_L, G_LT > 0 and
  // 1 − ν − 2 ν_LT² E/E_L > 0 (ν, E the transverse plane's).
  const Constituents& c = law.constituents;
  const Constituents iso = with_isotropic_axes(c);
  struct Phase {
    const char* name;
    double E, nu, E_L, nu_LT, G_LT;
    bool isotropic;
  };
  for (const Phase& p :
       {Phase{"fibre", c.fibre_E, c.fibre_nu, c.fibre_E_L, c.fibre_nu_LT, c.fibre_G_LT,
              c.fibre_E_L == iso.fibre_E_L && c.fibre_nu_LT == iso.fibre_nu_LT && c.fibre_G_LT == iso.fibre_G_LT},
        Phase{"matrix", c.matrix_E, c.matrix_nu, c.matrix_E_L, c.matrix_nu_LT, c.matrix_G_LT,
              c.matrix_E_L == iso.matrix_E_L && c.matrix_nu_LT == iso.matrix_nu_LT &&
                  c.matrix_G_LT == iso.matrix_G_LT}}) {
    const std::string nu = std::string(p.name) + "_nu";
    if (p.isotropic) {
      need(p.nu > -1 && p.nu < 0.5, nu.c_str(), p.nu, "(-1, 0.5)");
      continue;
    }
    need(p.nu > -1 && p.nu < 1, nu.c_str(), p.nu, "(-1, 1) (the transverse plane's, a transversely isotropic phase)");
    const std::string E_L = std::string(p.name) + "_E_L", G_LT = std::string(p.name) + "_G_LT",
                      nu_LT = std::string(p.name) + "_nu_LT";
    need(std::isfinite(p.E_L) && p.E_L > 0, E_L.c_str(), p.E_L, "> 0");
    need(std::isfinite(p.G_LT) && p.G_LT > 0, G_LT.c_str(), p.G_LT, "> 0");
    const Material phase{p.E, p.nu, true, p.E_L, p.nu_LT, p.G_LT};
    need(std::isfinite(p.nu_LT) && phase.compliance_margin() > 0, nu_LT.c_str(), p.nu_LT,
         "1 - nu - 2 nu_LT^2 E/E_L > 0");
  }
  need(law.constituents.fibre_volume_fraction >= 0 && law.constituents.fibre_volume_fraction < 1,
       "fibre_volume_fraction", law.constituents.fibre_volume_fraction, "[0, 1)");
}

OutOfPlane rule_of_mixtures(const Law& law) {
  const double Vf = law.constituents.fibre_volume_fraction;
  // Along the axis: E_L, ν_LT and G_LT of each phase (an isotropic phase's from E, ν).
  const Constituents& c = law.constituents;
  const double G_f = c.fibre_G_LT, G_m = c.matrix_G_LT;
  const double nu = Vf * c.fibre_nu_LT + (1 - Vf) * c.matrix_nu_LT;  // ν31 = ν32
  const double G = 1 / (Vf / G_f + (1 - Vf) / G_m);                  // 1/G13 = 1/G23 = Vf/G_f + (1 − Vf)/G_m
  return {Vf * c.fibre_E_L + (1 - Vf) * c.matrix_E_L, nu, nu, G, G};
}

OutOfPlane out_of_plane(const Law& law, int sign) {
  // The bonded state's (either sign: bonded, both are the same law), or the contact state's of the sign.
  for (const PlyState state : {PlyState::bonded, PlyState::contact})
    for (const PlyConstants& c : law.ply.rows)
      if (c.state == state && (state == PlyState::bonded ? c.sign == 1 : c.sign == sign))
        return {c.E1, c.nu12, c.nu13, c.G12, c.G13, true};
  return rule_of_mixtures(law);
}

SolidMaterial solid_material(const Eigen::Matrix3d& S_ps_in, const Law& law, const std::string& file,
                             const std::string& fit_name, int sign) {
  const std::string what = file + ": /law/" + fit_name;
  static const char* entry_names[3][3] = {
      {"xx,xx", "xx,yy", "xx,xy"}, {"yy,xx", "yy,yy", "yy,xy"}, {"xy,xx", "xy,yy", "xy,xy"}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(S_ps_in(i, j)))
        throw InputError(what + ": entry (" + entry_names[i][j] + ") is " + formatted("%g", S_ps_in(i, j)) +
                         ": the sweep does not determine it (a shear entry needs load directions off the axes or "
                         "stress_directions with shear), so no 3D material can be exported");
  const double scale = S_ps_in.cwiseAbs().maxCoeff();
  const double asymmetry = (S_ps_in - S_ps_in.transpose()).cwiseAbs().maxCoeff();
  if (!(scale > 0) || asymmetry > 1e-6 * scale)
    throw InputError(what + ": not symmetric (max |S_ij - S_ji| = " + formatted("%.3g", asymmetry) +
                     " of max |S_ij| = " + formatted("%.3g", scale) + "): not an elastic compliance");
  const Eigen::Matrix3d S_ps = (S_ps_in + S_ps_in.transpose()) / 2;
  const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S_ps).eigenvalues();
  // A singular or indefinite S_ps gives a 3D material with zero or negative strain energy.
  if (!(eigenvalues(0) > 1e-12 * eigenvalues(2)))
    throw InputError(what + ": not positive definite (eigenvalues " + formatted("%.4g", eigenvalues(0)) + ", " +
                     formatted("%.4g", eigenvalues(1)) + ", " + formatted("%.4g", eigenvalues(2)) +
                     "): no admissible elastic material reproduces it");
  check_constituents(law, file);

  SolidMaterial m;
  m.coupling = std::max(std::abs(S_ps(0, 2)) / std::sqrt(S_ps(0, 0) * S_ps(2, 2)),
                        std::abs(S_ps(1, 2)) / std::sqrt(S_ps(1, 1) * S_ps(2, 2)));
  m.orthotropic = m.coupling <= coupling_tolerance;

  const OutOfPlane z = out_of_plane(law, sign);
  // S13 = −ν31/E3, S23 = −ν32/E3, S33 = 1/E3.
  const double S13 = -z.nu31 / z.E3, S23 = -z.nu32 / z.E3, S33 = 1 / z.E3;
  auto& S = m.S;
  S(2, 2) = S33;
  S(0, 2) = S(2, 0) = S13;
  S(1, 2) = S(2, 1) = S23;
  // In plane: S_ij = S_ps,ij + S_i3 S_j3 / S33, so that ε33 = 0 gives back S_ps.
  S(0, 0) = S_ps(0, 0) + S13 * S13 / S33;
  S(1, 1) = S_ps(1, 1) + S23 * S23 / S33;
  S(0, 1) = S(1, 0) = S_ps(0, 1) + S13 * S23 / S33;
  // Shear γ12 (Voigt index 3): unchanged by σ33, since σ33 does not couple to γ12 (S34 = 0).
  S(3, 3) = S_ps(2, 2);
  if (!m.orthotropic) {
    S(0, 3) = S(3, 0) = S_ps(0, 2);
    S(1, 3) = S(3, 1) = S_ps(1, 2);
  }
  // Out-of-plane shears γ13, γ23.
  S(4, 4) = 1 / z.G13;
  S(5, 5) = 1 / z.G23;

  const Eigen::Matrix<double, 6, 1> eigenvalues_3d =
      Eigen::SelfAdjointEigenSolver<SolidMaterial::Matrix6d>(S).eigenvalues();
  if (!(eigenvalues_3d(0) > 1e-12 * eigenvalues_3d(5)))
    throw InputError(what + ": the 3D compliance is not positive definite (smallest eigenvalue " +
                     formatted("%.4g", eigenvalues_3d(0)) + "): not an admissible material");
  m.C = S.inverse();

  auto& k = m.constants;
  k.E1 = 1 / S(0, 0);
  k.E2 = 1 / S(1, 1);
  k.E3 = 1 / S(2, 2);
  // ν_ij = −S_ij E_i: ε_j = −ν_ij σ_i / E_i under σ_i alone (the CalculiX/Abaqus convention).
  k.nu12 = -S(0, 1) * k.E1;
  k.nu13 = -S(0, 2) * k.E1;
  k.nu23 = -S(1, 2) * k.E2;
  k.G12 = 1 / S(3, 3);
  k.G13 = 1 / S(4, 4);
  k.G23 = 1 / S(5, 5);
  return m;
}

}  // namespace dualcell::law
