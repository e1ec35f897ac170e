#include "io/solution_file.hpp"

#include <iterator>

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/fields_io.hpp"
#include "io/file_root.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace dualcell::io {

namespace {

std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

// /solver: how the solve ended, its counts (qp::counter_fields, solver_count_fields), its seconds
// (feti::setup_timing_fields, qp_timing_fields, operator_profile_fields) and settings; /kkt: its KKT residuals.
void write_solver(File& f, const mesh::Mesh& mesh, const Scene& scene, const feti::Solution& s) {
  f.create_group("/solver");
  f.write_attribute("/solver", "status", std::string(qp::to_string(s.qp.status)));
  f.write_attribute("/solver", "message", s.qp.message);
  f.write_attribute("/solver", "primal_ok", std::int64_t{s.primal_ok});
  f.write_attribute("/solver", "primal_message", s.primal_message);
  write_attributes(f, "/solver", qp::counter_fields, s.counters);
  write_attributes(f, "/solver", solver_count_fields, s);
  f.write_attribute("/solver", "dim_u", std::int64_t{mesh.dim_u()});
  write_attributes(f, "/solver", feti::setup_timing_fields, s.seconds, "seconds_");
  write_attributes(f, "/solver", feti::qp_timing_fields, s.seconds, "seconds_");
  write_attributes(f, "/solver", feti::operator_profile_fields, s.seconds.in_qp, "seconds_qp_", "s");
  f.write_attribute("/solver", "preconditioner", std::string(to_string(scene.solver.preconditioner)));
  f.write_attribute("/solver", "dual_operator", std::string(to_string(scene.solver.dual_operator)));
  f.write_attribute("/solver", "subdomains", std::int64_t{s.subdomains});
  f.write_attribute("/solver", "explicit_subdomains", std::int64_t{s.explicit_subdomains});
  f.write_attribute("/solver", "tolerance", scene.solver.tolerance);
  f.write_attribute("/solver", "qp_tolerance", s.qp_tolerance);
  f.create_group("/kkt");
  write_attributes(f, "/kkt", kkt_fields, s.kkt);
}

// /ranks: one row per rank that shared the solve (rank_columns).
void write_ranks(File& f, const RankTable& ranks) { write_columns(f, "/ranks", rank_columns, ranks); }

// /steps: the load steps of a block with Boundary::edges.
void write_steps(File& f, const LoadSteps& steps) {
  const hsize_t S = steps.factor.size();
  f.write("/steps/factor", steps.factor, {S});
  f.write("/steps/watch_displacement", steps.watch_displacement, {S, 2});
  f.write("/steps/newly_broken", steps.newly_broken, {S});
  f.write("/steps/broken", steps.broken, {S});
  f.write("/steps/converged", steps.converged, {S});
  f.write("/steps/operator_applications", steps.operator_applications, {S});
  f.write_attribute("/steps", "first_break_factor", steps.first_break_factor);
}

}  // namespace

void write_solution(const std::filesystem::path& h5, const mesh::Mesh& mesh, const Scene& scene,
                    const feti::Solution& s, const feti::SolutionFields& fields, const Provenance& provenance,
                    const LoadSteps* steps, const RankTable* ranks,
                    const primal::LongitudinalShear* longitudinal_shear) {
  const std::filesystem::path xdmf = xdmf_beside(h5);
  AtomicOutputs outputs;
  outputs.add(h5);
  outputs.add(xdmf);
  const hsize_t N = mesh.nodes.size(), T = mesh.triangles.size(), P = mesh.interface_pairs.size();
  // Exaggeration for the deformed view: the largest displacement drawn as 5 % of the block.
  const double u_max = s.u.head(mesh.dim_u()).lpNorm<Eigen::Infinity>();
  const double block = std::max(mesh.block_width(), mesh.block_height());
  const double scale = u_max > 0 ? 0.05 * block / u_max : 1.0;
  {
    File f = File::create(h5);
    // Mesh copied in, so that the file (and its XDMF) stands alone.
    std::vector<double> nodes, deformed, displacement;
    for (hsize_t v = 0; v < N; ++v)
      for (int c = 0; c < 2; ++c) {
        nodes.push_back(mesh.nodes[v][c]);
        deformed.push_back(mesh.nodes[v][c] + scale * s.u(2 * v + c));
      }
    for (hsize_t v = 0; v < N; ++v) displacement.insert(displacement.end(), {s.u(2 * v), s.u(2 * v + 1), 0.0});
    const hsize_t W = mesh.triangles.width();
    std::vector<std::int64_t> triangles(mesh.triangles.flat().begin(), mesh.triangles.flat().end()), subdomain;
    for (int sd : mesh.triangle_subdomain) subdomain.push_back(sd);
    f.write("/mesh/nodes", nodes, {N, 2});
    f.write("/mesh/triangles", triangles, {T, W});
    f.write("/mesh/triangle_subdomain", subdomain, {T});
    f.write("/solution/u", to_vector(s.u.head(mesh.dim_u())), {N, 2});
    f.write("/solution/displacement", displacement, {N, 3});
    f.write("/solution/deformed_nodes", deformed, {N, 2});
    f.write_attribute("/solution/deformed_nodes", "exaggeration", scale);
    // Per triangle: the stress at the centroid and its volume average (equal for p1).
    const fem::ElementStresses& stress = fields.stress;
    const auto rows = [](const Eigen::MatrixXd& m) {
      std::vector<double> out;
      for (Eigen::Index t = 0; t < m.rows(); ++t)
        for (int c = 0; c < 3; ++c) out.push_back(m(t, c));
      return out;
    };
    f.write("/solution/element_stress", rows(stress.centroid), {T, 3});
    f.write("/solution/element_stress_average", rows(stress.average), {T, 3});

    std::vector<double> lambda;
    std::vector<std::int64_t> bonded;
    for (hsize_t p = 0; p < P; ++p) {
      lambda.insert(lambda.end(), {s.normal_force[p], s.tangential_force[p]});
      bonded.push_back(s.bonds.empty() ? 0 : s.bonds[p]);
    }
    f.write("/interface/lambda", lambda, {P, 2});
    f.write("/interface/opening", fields.opening, {P});
    f.write("/interface/bonded", bonded, {P});

    f.write("/macro/stress", std::vector<double>{s.sigma(0), s.sigma(1), s.sigma(2)}, {3});
    f.write("/macro/strain", std::vector<double>{s.strain(0), s.strain(1), s.strain(2)}, {3});
    f.write("/macro/average_stress", std::vector<double>{s.average_stress(0), s.average_stress(1), s.average_stress(2)},
            {3});
    if (longitudinal_shear) {  // asked for only: a file without it stays as it was
      const Eigen::Matrix2d& G = longitudinal_shear->G;
      f.write("/macro/longitudinal_shear_moduli", std::vector<double>{G(0, 0), G(0, 1), G(1, 0), G(1, 1)}, {2, 2});
      f.write("/solution/longitudinal_w_xz", to_vector(longitudinal_shear->w_tilde.col(0)), {N});
      f.write("/solution/longitudinal_w_yz", to_vector(longitudinal_shear->w_tilde.col(1)), {N});
    }
    // Generalised plane strain or a temperature change only: a plane-strain file stays as it was.
    if (s.eps33 != 0 || s.delta_T != 0) {
      if (s.eps33 != 0) f.write("/macro/eps33", std::vector<double>{s.eps33}, {1});
      if (s.delta_T != 0) f.write("/macro/delta_T", std::vector<double>{s.delta_T}, {1});
      f.write("/macro/average_stress_zz", std::vector<double>{s.average_stress_zz}, {1});
      f.write("/solution/element_stress_zz_average", to_vector(stress.zz_average), {T});
    }

    write_solver(f, mesh, scene, s);
    if (ranks) write_ranks(f, *ranks);
    if (steps) write_steps(f, *steps);

    Provenance p = provenance;
    p.scene_text = scene.text;
    write_provenance(f, solution_format, p);
    outputs.write(h5, f.close_to_image());
  }
  const std::string name = h5.filename().string();
  XdmfGrid deformed;
  deformed.name = "deformed";
  deformed.nodes_dataset = "/solution/deformed_nodes";
  deformed.n_nodes = N;
  deformed.triangles_dataset = "/mesh/triangles";
  deformed.n_triangles = T;
  deformed.nodes_per_triangle = mesh.triangles.width();
  deformed.fields = {{"subdomain", "/mesh/triangle_subdomain", true, {T}, true},
                     {"stress", "/solution/element_stress", true, {T, 3}, false},
                     {"stress_average", "/solution/element_stress_average", true, {T, 3}, false},
                     {"displacement", "/solution/displacement", false, {N, 3}, false}};
  if (s.eps33 != 0 || s.delta_T != 0)
    deformed.fields.push_back({"stress_zz_average", "/solution/element_stress_zz_average", true, {T}, false});
  if (longitudinal_shear)
    for (const char* c : {"xz", "yz"})
      deformed.fields.push_back(
          {std::string("longitudinal_w_") + c, std::string("/solution/longitudinal_w_") + c, false, {N}, false});
  outputs.write(xdmf, xdmf_text(name, {deformed}));
  outputs.commit();
}

std::vector<double> pack(const RankEntry& entry) {
  std::vector<double> packed;
  for_each_field(rank_columns, entry, [&](const auto&, const auto& v) { packed.push_back(static_cast<double>(v)); });
  return packed;
}

RankTable unpack_rank_table(const std::vector<double>& packed) {
  constexpr std::size_t width = std::size(rank_columns);
  RankTable table(packed.size() / width);
  for (std::size_t r = 0; r < table.size(); ++r) {
    std::size_t k = r * width;
    for_each_field(rank_columns, table[r],
                   [&](const auto&, auto& v) { v = static_cast<std::remove_cvref_t<decltype(v)>>(packed[k++]); });
  }
  return table;
}

feti::BondState read_bonds(const std::filesystem::path& h5, const mesh::Mesh& mesh, const std::string& mesh_hash) {
  File f = File::open_read(h5);
  check_format(f, solution_format);
  if (f.read_string_attribute("/", "mesh_hash") != mesh_hash)
    throw InputError(h5.string() + ": its bond state was computed on another mesh (mesh_hash " +
                     f.read_string_attribute("/", "mesh_hash") + ", this mesh " + mesh_hash + ")");
  const auto bonded =
      f.read_ints("/interface/bonded", {mesh.interface_pairs.size()}, " (one per interface pair of the mesh)");
  feti::BondState bonds(bonded.size());
  for (std::size_t p = 0; p < bonded.size(); ++p) {
    if (bonded[p] != 0 && bonded[p] != 1) throw InputError(h5.string() + ": /interface/bonded: entries must be 0 or 1");
    bonds[p] = static_cast<std::uint8_t>(bonded[p]);
  }
  return bonds;
}

}  // namespace dualcell::io
