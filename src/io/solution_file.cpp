#include "core/version.hpp"
#include "io/solution_file.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "io/atomic_output.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace dualcell::io {

namespace {

std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

void write_solution(const std::filesystem::path& h5, const mesh::Mesh& mesh, const Scene& scene,
                    const feti::Solution& s, const SolutionProvenance& provenance) {
  std::filesystem::path xdmf = h5;
  xdmf.replace_extension(".xdmf");
  AtomicOutputs outputs;
  const auto h5_tmp = outputs.add(h5);
  const auto xdmf_tmp = outputs.add(xdmf);
  const hsize_t N = mesh.nodes.size(), T = mesh.triangles.size(), P = mesh.interface_pairs.size();
  // Exaggeration for the deformed view: the largest displacement drawn as 5 % of the block.
  const double u_max = s.u.head(mesh.dim_u()).lpNorm<Eigen::Infinity>();
  const double block = std::max(mesh.block_width(), mesh.block_height());
  const double scale = u_max > 0 ? 0.05 * block / u_max : 1.0;
  {
    File f = File::create(h5_tmp);
    // Mesh copied in, so that the file (and its XDMF) stands alone.
    std::vector<double> nodes, deformed, displacement;
    for (hsize_t v = 0; v < N; ++v)
      for (int c = 0; c < 2; ++c) {
        nodes.push_back(mesh.nodes[v][c]);
        deformed.push_back(mesh.nodes[v][c] + scale * s.u(2 * v + c));
      }
    for (hsize_t v = 0; v < N; ++v) displacement.insert(displacement.end(), {s.u(2 * v), s.u(2 * v + 1), 0.0});
    std::vector<std::int64_t> triangles, subdomain;
    for (const auto& t : mesh.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
    for (int sd : mesh.triangle_subdomain) subdomain.push_back(sd);
    f.write("/mesh/nodes", nodes, {N, 2});
    f.write("/mesh/triangles", triangles, {T, 3});
    f.write("/mesh/triangle_subdomain", subdomain, {T});
    f.write("/solution/u", to_vector(s.u.head(mesh.dim_u())), {N, 2});
    f.write("/solution/displacement", displacement, {N, 3});
    f.write("/solution/deformed_nodes", deformed, {N, 2});
    f.write_attribute("/solution/deformed_nodes", "exaggeration", scale);
    const Eigen::MatrixXd stress = fem::element_stresses(mesh, scene.fibre, scene.matrix, s.u);
    std::vector<double> stress_rows;
    for (int t = 0; t < stress.rows(); ++t)
      for (int c = 0; c < 3; ++c) stress_rows.push_back(stress(t, c));
    f.write("/solution/element_stress", stress_rows, {T, 3});

    std::vector<double> lambda, gap;
    std::vector<std::int64_t> bonded;
    for (hsize_t p = 0; p < P; ++p) {
      lambda.insert(lambda.end(), {s.normal_force[p], s.tangential_force[p]});
      const auto [fn, mn] = mesh.interface_pairs[p];
      const Eigen::Vector2d n = feti::interface_normal(mesh, static_cast<int>(p));
      gap.push_back(n.dot(s.u.segment<2>(2 * mn) - s.u.segment<2>(2 * fn)));
      bonded.push_back(s.bonds.empty() ? 0 : s.bonds[p]);
    }
    f.write("/interface/lambda", lambda, {P, 2});
    f.write("/interface/opening", gap, {P});
    f.write("/interface/bonded", bonded, {P});

    f.write("/macro/stress", std::vector<double>{s.sigma(0), s.sigma(1), s.sigma(2)}, {3});
    f.write("/macro/strain", std::vector<double>{s.strain(0), s.strain(1), s.strain(2)}, {3});
    f.write("/macro/average_stress", std::vector<double>{s.average_stress(0), s.average_stress(1), s.average_stress(2)}, {3});

    f.create_group("/solver");
    f.write_attribute("/solver", "status", std::string(qp::to_string(s.qp.status)));
    f.write_attribute("/solver", "message", s.qp.message);
    f.write_attribute("/solver", "primal_ok", std::int64_t{s.primal_ok});
    f.write_attribute("/solver", "primal_message", s.primal_message);
    f.write_attribute("/solver", "outer_iterations", std::int64_t{s.outer_iterations});
    f.write_attribute("/solver", "operator_applications", std::int64_t{s.operator_applications});
    f.write_attribute("/solver", "cg_steps", std::int64_t{s.cg_steps});
    f.write_attribute("/solver", "expansion_steps", std::int64_t{s.expansion_steps});
    f.write_attribute("/solver", "proportioning_steps", std::int64_t{s.proportioning_steps});
    f.write_attribute("/solver", "debond_rounds", std::int64_t{s.debond_rounds});
    f.write_attribute("/solver", "newly_broken", std::int64_t{s.newly_broken});
    f.write_attribute("/solver", "dim_u", std::int64_t{mesh.dim_u()});
    f.write_attribute("/solver", "dim_lambda", std::int64_t{s.n_rows});
    f.write_attribute("/solver", "seconds_assembly", s.seconds.assembly);
    f.write_attribute("/solver", "seconds_factorisation", s.seconds.factorisation);
    f.write_attribute("/solver", "seconds_dual_setup", s.seconds.dual_setup);
    f.write_attribute("/solver", "seconds_qp", s.seconds.qp);
    f.write_attribute("/solver", "seconds_recovery", s.seconds.recovery);
    f.write_attribute("/solver", "seconds_qp_F", s.seconds.qp_F);
    f.write_attribute("/solver", "seconds_qp_Q", s.seconds.qp_Q);
    f.write_attribute("/solver", "seconds_qp_preconditioner", s.seconds.qp_preconditioner);
    f.write_attribute("/solver", "preconditioner", std::string(to_string(scene.solver.preconditioner)));
    f.write_attribute("/solver", "preconditioner_applications", std::int64_t{s.preconditioner_applications});
    f.write_attribute("/solver", "tolerance", scene.solver.tolerance);
    f.create_group("/kkt");
    const feti::KktReport& k = s.kkt;
    f.write_attribute("/kkt", "relative_projected_gradient", k.relative_projected_gradient);
    f.write_attribute("/kkt", "relative_equality_residual", k.relative_equality_residual);
    f.write_attribute("/kkt", "bound_violation", k.bound_violation);
    f.write_attribute("/kkt", "complementarity", k.complementarity);
    f.write_attribute("/kkt", "max_penetration", k.max_penetration);
    f.write_attribute("/kkt", "max_glue_jump", k.max_glue_jump);
    f.write_attribute("/kkt", "relative_equilibrium", k.relative_equilibrium);

    f.write_attribute("/", "format", std::string("dualcell solution 1"));
    f.write_attribute("/", "code_version", std::string(code_version));
    f.write_attribute("/", "scene", scene.text);
    f.write_attribute("/", "mesh_file", provenance.mesh_file);
    f.write_attribute("/", "mesh_hash", provenance.mesh_hash);
  }
  const std::string name = h5.filename().string();
  XdmfGrid deformed;
  deformed.name = "deformed";
  deformed.nodes_dataset = "/solution/deformed_nodes";
  deformed.n_nodes = N;
  deformed.triangles_dataset = "/mesh/triangles";
  deformed.n_triangles = T;
  deformed.fields = {{"subdomain", "/mesh/triangle_subdomain", true, {T}, true},
                     {"stress", "/solution/element_stress", true, {T, 3}, false},
                     {"displacement", "/solution/displacement", false, {N, 3}, false}};
  write_xdmf(xdmf_tmp, name, {deformed});
  outputs.commit();
}

feti::BondState read_bonds(const std::filesystem::path& h5, const mesh::Mesh& mesh, const std::string& mesh_hash) {
  File f = File::open_read(h5);
  if (!f.has_attribute("/", "format") || f.read_string_attribute("/", "format") != "dualcell solution 1")
    throw InputError(h5.string() + ": not a dualcell solution file (root attribute format != \"dualcell solution 1\")");
  if (f.read_string_attribute("/", "mesh_hash") != mesh_hash)
    throw InputError(h5.string() + ": its bond state was computed on another mesh (mesh_hash " +
                     f.read_string_attribute("/", "mesh_hash") + ", this mesh " + mesh_hash + ")");
  std::vector<hsize_t> dims;
  const auto bonded = f.read_ints("/interface/bonded", &dims);
  if (dims.size() != 1 || dims[0] != mesh.interface_pairs.size())
    throw InputError(h5.string() + ": /interface/bonded: " + std::to_string(dims.empty() ? 0 : dims[0]) +
                     " entries, the mesh has " + std::to_string(mesh.interface_pairs.size()) + " interface pairs");
  feti::BondState bonds(bonded.size());
  for (std::size_t p = 0; p < bonded.size(); ++p) {
    if (bonded[p] != 0 && bonded[p] != 1) throw InputError(h5.string() + ": /interface/bonded: entries must be 0 or 1");
    bonds[p] = static_cast<std::uint8_t>(bonded[p]);
  }
  return bonds;
}

}  // namespace dualcell::io
