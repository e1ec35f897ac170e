#pragma once
// solution.h5: the output of dualcell-solve (layout in docs/reference/solution-h5.md), with an
// XDMF beside it that shows the deformed shape, gaps included, in ParaView.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/fields.hpp"
#include "core/provenance.hpp"
#include "core/scene.hpp"
#include "feti/macro.hpp"
#include "feti/solver.hpp"
#include "mesh/mesh.hpp"
#include "primal/antiplane.hpp"

namespace dualcell::io {

// The counters of a solve, written as integer attributes of /solver: those of the QPs
// (Solution::counters, qp::counter_fields) and these of the solve itself.
inline constexpr Field<feti::Solution, long> solver_count_fields[] = {
    {"debond_rounds", &feti::Solution::debond_rounds},
    {"newly_broken", &feti::Solution::newly_broken},
    {"dim_lambda", &feti::Solution::n_rows},
    {"tightenings", &feti::Solution::tightenings},
};

// Seconds per phase, as float attributes of /solver: seconds_<name> of feti::setup_timing_fields, qp_timing_fields and
// seconds_qp_<name> of the seconds of feti::operator_profile_fields (Timings::in_qp); the tables
// are walked, so a new phase reaches the file without an edit here.

// The KKT residuals, as float attributes of /kkt.
inline constexpr Field<feti::KktReport, double> kkt_fields[] = {
    {"relative_projected_gradient", &feti::KktReport::relative_projected_gradient},
    {"relative_equality_residual", &feti::KktReport::relative_equality_residual},
    {"bound_violation", &feti::KktReport::bound_violation},
    {"complementarity", &feti::KktReport::complementarity},
    {"max_penetration", &feti::KktReport::max_penetration},
    {"max_glue_jump", &feti::KktReport::max_glue_jump},
    {"relative_equilibrium", &feti::KktReport::relative_equilibrium},
};

// The load steps of a block with Boundary::edges (the solution written is the last step's).
struct LoadSteps {
  std::vector<double> factor;              // t per step
  std::vector<double> watch_displacement;  // (ux, uy) of the scene's watch point per step
  std::vector<std::int64_t> newly_broken;  // bonds broken in the step
  std::vector<std::int64_t> broken;        // bonds broken in all after the step
  std::vector<std::int64_t> converged;     // 1 when the step's solve converged and passed its check
  std::vector<std::int64_t> operator_applications;
  // t* at which the first bond of the intact interface reaches its strength (+inf without
  // adhesion), from one solve (feti::ContactSolver::debond_onset).
  double first_break_factor = 0;
};

// One entry per rank that shared the solve (one without MPI; docs/method.md §16): what it held
// and where its time went. /ranks in solution.h5.
// One rank's row of /ranks: what it owned and where its time went.
struct RankEntry {
  std::int64_t first_subdomain = 0, subdomains = 0, dofs = 0;  // its run of subdomains
  std::int64_t subdomain_bytes = 0;                            // K, R and the factors of its subdomains
  std::int64_t peak_rss_bytes = 0;                             // the process's peak resident memory
  double seconds_setup = 0;                                    // assembly and factorisation of its subdomains
  // Applying F and M⁻¹: its subdomains' share (K⁺, the preconditioner), and the exchanges.
  double seconds_apply = 0, seconds_communication = 0;
  std::int64_t exchanges = 0, bytes_received = 0;
};
using RankTable = std::vector<RankEntry>;  // one entry per rank, in rank order

// The columns of /ranks, one member of RankEntry each (exactly one member pointer set): the
// writer walks it, and so do the packing of an entry into doubles for the one gather over the
// ranks and its unpacking (counts are exact in a double up to 2^53).
inline constexpr Field<RankEntry, long, double> rank_columns[] = {
    {"first_subdomain", &RankEntry::first_subdomain},
    {"subdomains", &RankEntry::subdomains},
    {"dofs", &RankEntry::dofs},
    {"subdomain_bytes", &RankEntry::subdomain_bytes},
    {"peak_rss_bytes", &RankEntry::peak_rss_bytes},
    {"seconds_setup", &RankEntry::seconds_setup, 0, "s"},
    {"seconds_apply", &RankEntry::seconds_apply, 0, "s"},
    {"seconds_communication", &RankEntry::seconds_communication, 0, "s"},
    {"exchanges", &RankEntry::exchanges},
    {"bytes_received", &RankEntry::bytes_received},
};
std::vector<double> pack(const RankEntry& entry);
RankTable unpack_rank_table(const std::vector<double>& packed);  // the gathered packs, in rank order

// `fields`: feti::solution_fields of the solution. `provenance` names the mesh (mesh_file,
// mesh_hash); the scene's text is taken from `scene`. `steps`, when given, is written to /steps.
void write_solution(const std::filesystem::path& h5, const mesh::Mesh& mesh, const Scene& scene,
                    const feti::Solution& solution, const feti::SolutionFields& fields, const Provenance& provenance,
                    const LoadSteps* steps = nullptr, const RankTable* ranks = nullptr,
                    const primal::LongitudinalShear* longitudinal_shear = nullptr);

// The bond state stored in a solution file (/interface/bonded), checked against the mesh: the
// file must have been solved on the mesh whose hash is `mesh_hash`.
feti::BondState read_bonds(const std::filesystem::path& h5, const mesh::Mesh& mesh, const std::string& mesh_hash);

}  // namespace dualcell::io
