// dualcell-solve: one load case through the dual contact/adhesion solver.
//
// Reads the scene and its mesh, applies the macroscopic stress σ̄ = (σxx, σyy, σxy) through the
// scene's boundary condition, solves the Total FETI dual problem with SMALBE/MPRGP (breaking
// bonds at their strength and re-solving, METHOD §6), recovers u, and writes solution.h5 with
// an XDMF of the deformed shape (gaps visible). Prints a one-screen summary with the time of
// each phase.
//
//   dualcell-solve --config scene.toml --mesh mesh.h5 --stress 0.01,0,0 --out solution.h5
#include <cmath>
#include <cstdio>
#include <sstream>

#include <CLI/CLI.hpp>

#include "core/error.hpp"
#include "core/scene.hpp"
#include "core/stage.hpp"
#include "feti/solver.hpp"
#include "io/hash.hpp"
#include "io/mesh_file.hpp"
#include "io/solution_file.hpp"

namespace {

Eigen::Vector3d parse_stress(const std::string& text) {
  std::stringstream in(text);
  Eigen::Vector3d sigma;
  std::string item;
  int i = 0;
  while (std::getline(in, item, ',')) {
    if (i >= 3) break;
    try {
      std::size_t used = 0;
      sigma(i) = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(sigma(i))) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw dualcell::InputError("--stress " + text + ": '" + item + "' is not a finite number");
    }
    ++i;
  }
  if (i != 3 || std::getline(in, item))
    throw dualcell::InputError("--stress " + text + ": expected three numbers sxx,syy,sxy");
  return sigma;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dualcell-solve: one macroscopic stress through the dual (Total FETI) contact/adhesion solver.\n"
               "Writes solution.h5 and solution.xdmf (layout: README.md, \"solution.h5\")."};
  std::string config, mesh_file, stress_text, out, bonds_file;
  bool quiet = false;
  app.add_option("--config", config, "scene file (TOML)")->required();
  app.add_option("--mesh", mesh_file, "mesh.h5 made by dualcell-mesh from the same scene")->required();
  app.add_option("--stress", stress_text, "macroscopic stress sxx,syy,sxy (tensor shear)")->required();
  app.add_option("--out", out, "output HDF5 file; the XDMF file is written beside it")->required();
  app.add_option("--bonds", bonds_file, "solution.h5 whose /interface/bonded is the bond state before this load "
                                        "(default: intact)");
  app.add_flag("--quiet", quiet, "do not print the summary");
  int threads = 0;
  app.add_option("--threads", threads, "threads for the subdomain work; 0 = OMP_NUM_THREADS or all cores (results do not depend on it)")
      ->check(CLI::Range(0, 4096));
  CLI11_PARSE(app, argc, argv);

  int exit_code = dualcell::exit_ok;
  const int status = dualcell::run_stage("dualcell-solve", [&] {
    using namespace dualcell;
    const Eigen::Vector3d sigma = parse_stress(stress_text);
    const Scene scene = load_scene(config);
    for (const auto& w : scene.warnings) std::fprintf(stderr, "dualcell-solve: warning: %s\n", w.c_str());
    const io::MeshFile mesh_in = io::read_mesh(mesh_file);
    const std::string mismatch = io::geometry_mismatch(mesh_in.mesh, scene);
    if (!mismatch.empty())
      throw InputError(mesh_file + ": made from a different scene than " + config + ": " + mismatch);
    if (scene.load.boundary == Boundary::symmetry && sigma(2) != 0)
      throw InputError("--stress " + stress_text + ": the symmetry boundary carries only sxx and syy (sxy must be 0); "
                       "use boundary = \"traction\" or \"periodic\" for shear");
    const mesh::Mesh& mesh = mesh_in.mesh;
    feti::ContactSolver solver(mesh, scene, threads);
    const std::string mesh_hash = io::file_hash(mesh_file);
    const feti::BondState bonds = bonds_file.empty() ? solver.intact() : io::read_bonds(bonds_file, mesh, mesh_hash);
    const feti::Solution s = solver.solve(sigma, bonds);
    io::write_solution(out, mesh, scene, s, {mesh_file, mesh_hash});
    if (!s.qp_converged()) {
      std::fprintf(stderr, "dualcell-solve: warning: the solver stopped with status %s: %s (output written)\n",
                   qp::to_string(s.qp.status), s.qp.message.c_str());
      exit_code = 4;
    } else if (!s.primal_ok) {
      std::fprintf(stderr, "dualcell-solve: warning: %s (output written)\n", s.primal_message.c_str());
      exit_code = 4;
    }
    if (quiet) return;
    int broken = 0;
    for (auto b : s.bonds) broken += b == 0;
    std::printf("dualcell-solve: %s + %s, stress (%g, %g, %g) -> %s\n", config.c_str(), mesh_file.c_str(), sigma(0),
                sigma(1), sigma(2), out.c_str());
    std::printf("  boundary %s, adhesion %s, dim u %d, dim lambda %d\n", to_string(scene.load.boundary),
                scene.interface.has_adhesion() ? "yes" : "no", mesh.dim_u(), s.n_rows);
    std::printf("  status %s: %ld outer iterations, %ld operator applications (%ld CG, %ld expansion, %ld proportioning)\n",
                qp::to_string(s.qp.status), s.outer_iterations, s.operator_applications, s.cg_steps,
                s.expansion_steps, s.proportioning_steps);
    if (scene.interface.has_adhesion())
      std::printf("  bonds: %d debond rounds, %d broken now, %d broken in all of %zu\n", s.debond_rounds,
                  s.newly_broken, broken, s.bonds.size());
    std::printf("  macro strain  exx %.6e  eyy %.6e  exy %.6e\n", s.strain(0), s.strain(1), s.strain(2));
    std::printf("  Hill-Mandel   <s> - s_applied = (%.2e, %.2e, %.2e)\n", s.average_stress(0) - sigma(0),
                s.average_stress(1) - sigma(1), s.average_stress(2) - sigma(2));
    std::printf("  KKT: projected gradient %.2e (rel), |G l - e| %.2e (rel), bound violation %.2e,\n"
                "       complementarity %.2e, penetration %.2e, glue jump %.2e, equilibrium %.2e (rel)\n",
                s.kkt.relative_projected_gradient, s.kkt.relative_equality_residual, s.kkt.bound_violation,
                s.kkt.complementarity, s.kkt.max_penetration, s.kkt.max_glue_jump, s.kkt.relative_equilibrium);
    std::printf("  seconds: assembly %.3f, factorisation %.3f, dual setup %.3f, QP %.3f (F %.3f, Q %.3f, M^-1 %.3f), "
                "recovery %.3f; %d thread(s)\n",
                s.seconds.assembly, s.seconds.factorisation, s.seconds.dual_setup, s.seconds.qp, s.seconds.qp_F,
                s.seconds.qp_Q, s.seconds.qp_preconditioner, s.seconds.recovery,
                solver.setup().parallel() ? solver.setup().threads() : 1);
    if (scene.solver.preconditioner != Preconditioner::none)
      std::printf("  preconditioner %s: %ld applications\n", to_string(scene.solver.preconditioner),
                  s.preconditioner_applications);
  });
  return status != dualcell::exit_ok ? status : exit_code;
}
