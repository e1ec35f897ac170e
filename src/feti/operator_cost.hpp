#pragma once
// When a subdomain's explicit dual operator pays (docs/method.md §6a). One application of F
// costs each subdomain s either
//
//   implicit:  two sparse triangular sweeps with its factor L_s,    t_I = c_sweep · nnz(L_s)
//   explicit:  one dense product with F_s (n_s × n_s, n_s its rows), t_E = c_gemv · n_s²
//
// and the explicit one first costs a factorisation with its b boundary DOFs ordered last (the
// present one's multiply-adds φ(L_s) again, plus the dense trailing block's b³/3, both at the
// simplicial factorisation's rate) and the dense K_s⁺(b, b) from that block (a triangular
// inverse and a product, ⅔ b³ flops at Eigen's dense rate):
//
//   t_S = c_factor · (φ(L_s) + b³/3) + c_dense · ⅔ b³.
//
// It pays over A applications when A (t_I − t_E) > t_S, A the caller's expected number of QPs
// times applications_per_qp. The constants are this machine's, measured by `dualcell-bench`
// (table operators.md prints the model beside the measured seconds per subdomain kind, so a
// drift shows); they decide where the line falls, not what is computed: both operators give
// the same solution to the QP's tolerance.
#include <Eigen/Core>
#include <cmath>

#include "linalg/fixing_node_inverse.hpp"

namespace dualcell::feti {

struct OperatorCost {
  // Seconds per nonzero of L per application (both sweeps with the gather and scatter), per
  // entry of F_s per dense product, per multiply-add of the simplicial factorisation, and per
  // flop of the dense inverse.
  static constexpr double c_sweep = 1.4e-9, c_gemv = 0.1e-9, c_factor = 0.7e-9, c_dense = 0.4e-9;
  // A dense F_s larger than a core's cache is read from memory at every product: 0.44 ns per
  // entry for the 36-fibre RVE's matrix subdomain (1 786 rows, 25.5 MB), 0.57 for the 64-fibre
  // one's (2 918 rows, 68 MB), where c_gemv (0.1) was measured on F_s of at most 0.5 MB. Unknown
  // in between; the cache is this machine's 2 MiB of L2 per core. Without this rate the 36-fibre
  // RVE's sweep of 1 600 paths made its matrix explicit and ran 3.4 times slower per product.
  static constexpr double c_gemv_memory = 0.5e-9, cache_bytes = 2.0 * 1024 * 1024;
  // Applications of F per QP (with the norm estimate of a cold problem): one solve of the bench's
  // cells takes 150–260, a sweep's paths from the cached problem fewer.
  static constexpr double applications_per_qp = 200;

  double implicit_apply = 0, explicit_apply = 0, explicit_setup = 0;  // seconds

  static OperatorCost of(const linalg::FixingNodeInverse& K_plus, Eigen::Index rows, Eigen::Index boundary_dofs) {
    const double b = static_cast<double>(boundary_dofs), n = static_cast<double>(rows);
    const double gemv = 8 * n * n <= cache_bytes ? c_gemv : c_gemv_memory;
    return {c_sweep * static_cast<double>(K_plus.factor_nonzeros()), gemv * n * n,
            c_factor * (K_plus.factor_flops() + b * b * b / 3) + c_dense * 2.0 / 3.0 * b * b * b};
  }
  bool explicit_pays(double expected_qps) const {
    return expected_qps * applications_per_qp * (implicit_apply - explicit_apply) > explicit_setup;
  }
};

}  // namespace dualcell::feti
