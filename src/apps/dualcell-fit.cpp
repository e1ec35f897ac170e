// dualcell-fit: the effective bilinear tension/compression law from a sweep.
//
// Per direction: E_tension, E_compression (apparent plane-strain moduli s/ε_nn, least squares
// through the origin on the points before any break) with standard errors and R², Poisson's
// ratios, and where adhesion breaks the fuse stress, strain jump and the modulus past it; over
// all directions the in-plane compliances S_tension, S_compression with their residuals and
// definiteness, the cone-wise linear check, the cone-wise law before and after the fuse, and
// the exact onset surface checked against the sweep. Writes law.h5 (layout: README.md, "law.h5").
//
//   dualcell-fit --sweep sweep.h5 --out law.h5
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "apps/options.hpp"
#include "stage/law.hpp"
#include "stage/stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-fit: fit the bilinear tension/compression law to a sweep and write law.h5\n"
      "(layout: README.md, \"law.h5\")."};
  std::string sweep_file, out;
  bool quiet = false;
  app.add_option("--sweep", sweep_file, "sweep.h5 written by dualcell-sweep")->required();
  app.add_option("--out", out, "output HDF5 file")->required();
  app.add_flag("--quiet", quiet, "do not print the table");
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  return dualcell::run_stage("dualcell-fit", [&] {
    using namespace dualcell;
    const law::Law law = stage::run_fit(sweep_file, out);
    if (quiet) return;
    std::printf("dualcell-fit: %s -> %s (%zu directions)\n", sweep_file.c_str(), out.c_str(), law.directions.size());
    std::printf("  %8s %12s %10s %12s %10s %8s %8s %8s %12s %10s\n", "theta", "E_tension", "se", "E_compress", "se",
                "Ec/Et", "nu_t", "nu_c", "fuse_stress", "jump x");
    for (const auto& d : law.directions)
      std::printf("  %8.2f %12.5g %10.2e %12.5g %10.2e %8.4f %8.4f %8.4f %12.5g %10.3g\n", d.direction_deg, d.E_tension,
                  d.E_tension_se, d.E_compression, d.E_compression_se, d.E_compression / d.E_tension, d.nu_tension,
                  d.nu_compression, d.fuse_stress, d.fuse_strain_ratio);
    for (const auto* fit : {&law.tension, &law.compression}) {
      std::printf("  S_%s (engineering shear), rank %d, relative residual %.2e, %s:\n",
                  fit == &law.tension ? "tension" : "compression", fit->rank, fit->relative_residual,
                  fit->rank < 6 ? "not all entries determined by these directions"
                                : (fit->symmetric_positive_definite ? "SPD" : "NOT positive definite"));
      for (int i = 0; i < 3; ++i) std::printf("    %14.6e %14.6e %14.6e\n", fit->S(i, 0), fit->S(i, 1), fit->S(i, 2));
    }
    if (!std::isnan(law.cone_rank_one_ratio))
      std::printf("  cone-wise linear (Curnier-He-Zysset): rank-one ratio %.3f -> %s\n", law.cone_rank_one_ratio,
                  law.cone_wise_linear ? "yes" : "no (the stiffness jump is not rank-one)");
    // The fitted laws' apparent moduli E = s/ε_nn under uniaxial stress ±n⊗n, beside the measured ones.
    const auto law_modulus = [](const law::ConeLaw& cone, double theta_deg, double sign) {
      const double t = theta_deg * std::numbers::pi / 180, c = std::cos(t), s = std::sin(t);
      const Eigen::Vector3d e = law::strain_for(cone, sign * Eigen::Vector3d(c * c, s * s, c * s));
      return sign / (c * c * e(0) + s * s * e(1) + c * s * e(2));
    };
    for (const auto* cone : {&law.cone, &law.cone_after_fuse}) {
      const char* name = cone == &law.cone ? "cone-wise law" : "cone-wise law after the fuse";
      if (!cone->ok) {
        std::printf("  %s: none (%s)\n", name, cone->message.c_str());
        continue;
      }
      std::printf("  %s: %s, %zu planes, relative residual %.3g over %d points (one plane %.3g, struts %.3g)\n", name,
                  cone->form.c_str(), cone->law.c.size(), cone->relative_residual, cone->n_points,
                  cone->one_plane_residual, cone->struts_residual);
      std::printf("    %8s %12s %12s\n", "theta", "E_tension", "E_compress");
      for (const auto& d : law.directions)
        std::printf("    %8.2f %12.5g %12.5g\n", d.direction_deg, law_modulus(cone->law, d.direction_deg, 1),
                    law_modulus(cone->law, d.direction_deg, -1));
    }
    const law::OnsetSurface& onset = law.onset;
    if (onset.linear) {
      double worst = 0;
      int checked = 0;
      for (std::size_t k = 0; k < onset.path_onset.size(); ++k) {
        if (std::isnan(onset.path_sweep_onset[k])) continue;
        worst = std::max(worst, std::abs(onset.path_onset[k] / onset.path_sweep_onset[k] - 1));
        ++checked;
      }
      std::printf("  onset surface: %ld facets; predicts the onset of %d swept paths to %.2e relative\n",
                  static_cast<long>(onset.facets.rows()), checked, worst);
    } else {
      std::printf("  onset surface: none (%s)\n", onset.message.c_str());
    }
  });
}
