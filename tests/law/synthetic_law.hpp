#pragma once
// A synthetic but realistic Law (glass/epoxy constituents, an orthotropic tension compliance
// with E_x ≠ E_y and a stiffer compression one), with every field set to a distinct known value
// and NaN where the format allows it, so that round trips and exports can be checked field by
// field without the fit stage.
#include <cmath>
#include <limits>
#include <numbers>

#include "law/law.hpp"

namespace dualcell::testing {

inline Eigen::Matrix3d plane_strain_compliance(double E_x, double E_y, double nu_xy, double G_xy) {
  Eigen::Matrix3d S;
  // Engineering shear: γxy = σxy/G; ν_xy = −ε_yy/ε_xx under σxx alone.
  S << 1 / E_x, -nu_xy / E_x, 0,  //
      -nu_xy / E_x, 1 / E_y, 0,   //
      0, 0, 1 / G_xy;
  return S;
}

inline law::Law synthetic_law() {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  law::Law law;
  const double degrees[] = {0, 30, 60, 90};
  for (int i = 0; i < 4; ++i) {
    law::DirectionLaw d;
    d.direction_deg = degrees[i];
    d.E_tension = 6.0 + i;
    d.E_tension_se = 0.01 * (i + 1);
    d.E_tension_r2 = 0.999 - 0.001 * i;
    d.n_tension = 5 + i;
    d.E_compression = 9.0 + 0.5 * i;
    d.E_compression_se = 0.02 * (i + 1);
    d.E_compression_r2 = 0.9999;
    d.n_compression = 6;
    d.nu_tension = 0.45 - 0.01 * i;
    d.nu_tension_se = 1e-3;
    d.nu_compression = 0.42;
    d.nu_compression_se = 2e-3;
    // Adhesion breaks along 0° and 30° only.
    const bool breaks = i < 2;
    d.onset_stress = breaks ? 0.05 + 0.01 * i : nan;
    d.fuse_stress = breaks ? 0.0586 + 0.01 * i : nan;
    d.fuse_stress_after = breaks ? 0.0587 + 0.01 * i : nan;
    d.fuse_strain_jump = breaks ? 0.0114 : nan;
    d.fuse_strain_ratio = breaks ? 8.9 : nan;
    d.E_after_fuse = breaks ? 1.25 : nan;
    d.E_after_fuse_se = breaks ? 0.03 : nan;
    law.directions.push_back(d);
  }
  law.tension.S = plane_strain_compliance(6.0, 8.0, 0.4, 2.5);
  law.tension.S_se = Eigen::Matrix3d::Constant(1e-4);
  law.tension.S_se(2, 2) = nan;
  law.tension.rank = 6;
  law.tension.relative_residual = 0.012;
  law.tension.direction_residual = {0.01, 0.02, nan, 0.015};
  law.tension.symmetric_positive_definite = true;
  law.tension.n_points = 20;
  law.compression.S = plane_strain_compliance(9.0, 10.0, 0.42, 3.2);
  law.compression.S_se = Eigen::Matrix3d::Constant(2e-4);
  law.compression.rank = 5;
  law.compression.relative_residual = 0.004;
  law.compression.direction_residual = {0.001, 0.002, 0.003, 0.004};
  law.compression.symmetric_positive_definite = true;
  law.compression.n_points = 24;
  law.cone_rank_one_ratio = 0.031;
  law.cone_wise_linear = true;
  law.cone_normal = Eigen::Vector3d(0.8, 0.6, 0.0);
  law.cone_beta = 2.75;
  // The cone-wise fits: an admissible law before the fuse; none after it (too few points).
  law.cone.law.C_c << 8.5, 2.9, 0.1, 2.9, 9.7, -0.2, 0.1, -0.2, 3.1;
  law.cone.law.q = {Eigen::Vector3d(0.6, 0.8, 0.0), Eigen::Vector3d(0.0, 0.0, 1.0)};
  law.cone.law.beta = {2.5, 0.75};
  law.cone.form = "compression struts";
  law.cone.relative_residual = 0.021;
  law.cone.one_plane_residual = 0.05;
  law.cone.struts_residual = 0.021;
  law.cone.direction_residual = {0.011, 0.025, nan, 0.019};
  law.cone.n_points = 44;
  law.cone.ok = true;
  law.cone_after_fuse.direction_residual = {nan, nan, nan, nan};
  law.cone_after_fuse.n_points = 2;
  law.cone_after_fuse.message = "fewer than 3 points";
  law.cone_after_fuse.one_plane_residual = law.cone_after_fuse.struts_residual = nan;
  // An onset surface of three facets (two normal, one tangential), checked on two paths.
  law.onset.linear = true;
  law.onset.facets.resize(3, 3);
  law.onset.facets << 20.0, -1.5, 0.0, -2.0, 4.0, 0.5, 0.0, 0.0, 33.0;
  law.onset.pair = {4, 7, 7};
  law.onset.tangential = {0, 0, 1};
  law.onset.path_stress = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0)};
  law.onset.path_onset = {0.05, 0.5};
  law.onset.path_sweep_onset = {0.05, nan};
  // Glass/epoxy (materials/glass-epoxy.toml), fibre radius 0.3 in a unit cell: Vf = π 0.3².
  law.constituents.fibre_E = 72;
  law.constituents.fibre_nu = 0.22;
  law.constituents.matrix_E = 3.5;
  law.constituents.matrix_nu = 0.35;
  law.constituents.fibre_volume_fraction = std::numbers::pi * 0.09;
  law.constituents.cell_size = 1.0;
  law.constituents = with_isotropic_axes(law.constituents);
  law.units = "GPa (the scene's units); strains dimensionless";
  law.provenance.scene_text = "[geometry]\nfibre_radius = 0.3\n# a \"quoted\" comment\twith a tab\n";
  law.provenance.sweep_file = "sweep.h5";
  law.provenance.sweep_hash = "0123456789abcdef";
  law.provenance.solver_options = "tolerance=1e-08; max_outer_iterations=200";
  law.provenance.code_version = "0.1.0+test";
  return law;
}

}  // namespace dualcell::testing
