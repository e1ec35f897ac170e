#include "law/condensed_members.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/text.hpp"

namespace dualcell::law {

namespace {

bool symmetric(const Eigen::MatrixXd& M) {
  return M.rows() == M.cols() && (M - M.transpose()).norm() <= 1e-12 * std::max(M.norm(), 1e-300);
}

// The volume and every matrix's largest entry lie within 10^±100: the evaluation multiplies up to
// three of them (|Ω| S₀ ε̄ in the strain-driven QP), which then stay normal doubles (10^±308).
// Lengths from 10⁻⁵⁰ to 10⁵⁰ in any unit pass.
constexpr double magnitude_limit = 1e100;

bool in_magnitude(double size) { return size >= 1 / magnitude_limit && size <= magnitude_limit; }

// The smallest pivot of the Cholesky factor of the equilibrated energy (unit diagonal) that
// tells a positive definite matrix from a singular one: the factorisation's backward error is a
// small multiple of N ε (docs/method.md §16a), so a pivot below 64 N ε could be round-off of a
// zero. The cells of the pipelines have 5e-3 or more.
double pivot_floor(Eigen::Index N) { return 64.0 * static_cast<double>(N) * std::numeric_limits<double>::epsilon(); }

}  // namespace

std::size_t CondensedCell::bytes() const {
  std::size_t bytes = 0;
  for_each_member(*this, [&](const Member&, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (ArrayMember<T>)
      bytes += static_cast<std::size_t>(value.size()) * sizeof(double);
    else if constexpr (ListMember<T>)
      bytes += value.size() * sizeof(typename T::value_type);
  });
  return bytes;
}

long extent_limit(Extent e) {
  switch (e) {
    case Extent::one:
      return 1;
    case Extent::macro:
      return 3;
    case Extent::rows:
    case Extent::pairs:
    case Extent::fibre_modes:
      return max_cell_rows;
    case Extent::longitudinal:
      return 1;
  }
  return 0;
}

long extent(const CondensedCell& cell, Extent e) {
  switch (e) {
    case Extent::one:
      return 1;
    case Extent::macro:
      return cell.n_macro;
    case Extent::rows:
      return cell.n_rows();
    case Extent::pairs:
      return cell.n_pairs;
    case Extent::fibre_modes:
      return cell.G.rows();
    case Extent::longitudinal:
      return cell.longitudinal;
  }
  return 0;
}

const char* extent_name(Extent e) {
  switch (e) {
    case Extent::one:
      return "1";
    case Extent::macro:
      return "n_macro";
    case Extent::rows:
      return "n_rows";
    case Extent::pairs:
      return "n_pairs";
    case Extent::fibre_modes:
      return "fibre_modes";
    case Extent::longitudinal:
      return "longitudinal";
  }
  return "";
}

namespace {

// The counts in their ranges, the scalars' rules and every array's shape: the sizes the other
// checks rely on.
std::optional<CellProblem> size_problem(const CondensedCell& cell) {
  std::optional<CellProblem> found;
  const auto report = [&](std::string what) {
    if (!found) found = CellProblem{"", std::move(what)};
  };
  for_each_member(cell, [&](const Member& m, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const std::string name = m.name;
    if constexpr (CountMember<T>) {
      if (value < m.lo || value > m.hi)
        report(name + " is " + std::to_string(value) + ", not in [" + std::to_string(m.lo) + ", " +
               std::to_string(m.hi) + "]");
    } else if constexpr (RealMember<T>) {
      if (m.values == Values::positive && !(value > 0 && std::isfinite(value)))
        report(name + " is not positive and finite");
      else if (m.values == Values::positive && !in_magnitude(value))
        report(name + " is " + formatted("%.3g", value) + ", not within 1e-100 … 1e100");
    } else if constexpr (ArrayMember<T> || ListMember<T>) {
      long rows = static_cast<long>(value.size()), cols = 1;
      if constexpr (ArrayMember<T>) rows = value.rows(), cols = value.cols();
      // G's rows (fibre_modes) are its own, and without any its columns do not matter.
      const bool free_rows = m.rows == Extent::fibre_modes;
      // Without longitudinal data (extent 0) its arrays may be empty of any shape.
      const bool none = (m.rows == Extent::longitudinal || m.cols == Extent::longitudinal) && cell.longitudinal == 0 &&
                        rows * cols == 0;
      const bool shaped = none || ((free_rows || rows == extent(cell, m.rows)) &&
                                   (cols == extent(cell, m.cols) || (free_rows && rows == 0)));
      if (!shaped)
        report(name + " is not " + extent_name(m.rows) +
               (m.cols == Extent::one ? std::string(" long") : std::string(" × ") + extent_name(m.cols)));
    }
  });
  return found;
}

// The arrays' values, rule by rule: finite, symmetric, positive definite, then per entry.
std::optional<CellProblem> value_problem(const CondensedCell& cell) {
  bool finite = true, symmetric_all = true;
  std::string symmetric_names, not_definite;
  std::optional<CellProblem> entry;
  for_each_member(cell, [&](const Member& m, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const auto report = [&](std::string what) {
      if (!entry) entry = CellProblem{m.name, std::move(what)};
    };
    if constexpr (ArrayMember<T>) {
      if (m.values >= Values::finite && m.values <= Values::symmetric_positive_definite)
        finite = finite && value.allFinite();
      if (m.values == Values::symmetric || m.values == Values::symmetric_positive_definite) {
        symmetric_names += (symmetric_names.empty() ? "" : " or ") + std::string(m.name);
        symmetric_all = symmetric_all && symmetric(value);
      }
      if (m.values == Values::symmetric_positive_definite && not_definite.empty() && value.allFinite() &&
          Eigen::LLT<Eigen::MatrixXd>(value).info() != Eigen::Success)
        not_definite = m.name;
      if (m.values >= Values::finite && m.values <= Values::symmetric_positive_definite && value.size() > 0 &&
          value.allFinite()) {
        const double size = value.cwiseAbs().maxCoeff();
        if (size > 0 && !in_magnitude(size))
          report("its largest entry is " + formatted("%.3g", size) + ", not within 1e-100 … 1e100");
      }
      for (Eigen::Index r = 0; r < value.size(); ++r)
        if ((m.values == Values::at_most_zero && !(value.coeff(r) <= 0)) ||
            (m.values == Values::at_least_zero && !(value.coeff(r) >= 0)))
          report("row " + std::to_string(r) + ": its bounds do not hold 0");
    } else if constexpr (ListMember<T>) {
      const std::string of = m.rows == Extent::pairs ? "pair " : "row ";
      for (std::size_t r = 0; r < value.size(); ++r) {
        const long v = value[r];
        if (m.values == Values::zero_one && v != 0 && v != 1)
          report(std::to_string(v) + " is not 0 or 1 (" + of + std::to_string(r) + ")");
        if (m.values == Values::pair_index && (v < 0 || v >= cell.n_pairs))
          report(std::to_string(v) + " is not a pair index (" + of + std::to_string(r) + ")");
      }
    }
  });
  if (!finite) return CellProblem{"", "non-finite entries"};
  if (!symmetric_all) return CellProblem{"", symmetric_names + " is not symmetric"};
  if (!not_definite.empty()) return CellProblem{"", not_definite + " is not positive definite"};
  return entry;
}

// 𝓗 positive definite on the kernel of the fibres' rows [0 G]: the strain-driven law is then
// strictly convex on every admissible set, and each of its QPs has one solution. 𝓗 + CᵀC is
// factorised, equilibrated (𝓗's diagonal scaled to 1, the rows C = [0 G] to unit length): that
// is positive definite if and only if 𝓗 is on ker C, given 𝓗 positive semidefinite, which a
// cell's energy is; an indefinite 𝓗 fails either way.
std::optional<CellProblem> convexity_problem(const CondensedCell& cell) {
  Eigen::MatrixXd M = energy_matrix(cell);
  const Eigen::Index N = M.rows(), n = cell.n_rows();
  Eigen::VectorXd d(N);
  for (Eigen::Index i = 0; i < N; ++i) {
    if (!(M(i, i) > 0))
      return CellProblem{"", "the energy [|Ω|S0 −Yᵀ; −Y H] has a diagonal entry ≤ 0 (row " + std::to_string(i) +
                                 "): the law is not convex"};
    d(i) = 1 / std::sqrt(M(i, i));
  }
  M = d.asDiagonal() * M * d.asDiagonal();
  if (cell.G.rows() > 0) {
    Eigen::MatrixXd C = cell.G * d.tail(n).asDiagonal();
    for (Eigen::Index g = 0; g < C.rows(); ++g)
      if (const double norm = C.row(g).norm(); norm > 0) C.row(g) /= norm;
    M.bottomRightCorner(n, n).noalias() += C.transpose() * C;
  }
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(M);
  const double smallest = llt.info() == Eigen::Success ? M.diagonal().cwiseAbs2().minCoeff() : 0.0;
  if (!(smallest >= pivot_floor(N)))
    return CellProblem{"",
                       "the energy [|Ω|S0 −Yᵀ; −Y H] is not positive definite on G p = 0 (smallest equilibrated "
                       "pivot " +
                           formatted("%.3g", smallest) + ", below " + formatted("%.3g", pivot_floor(N)) +
                           "): the law is not convex"};
  return std::nullopt;
}

}  // namespace

std::optional<CellProblem> find_problem(const CondensedCell& cell) {
  if (auto problem = size_problem(cell)) return problem;
  if (auto problem = value_problem(cell)) return problem;
  // The open cell stretched along the fibres at σ̄ = 0 stores energy: C33 > 0.
  if (cell.longitudinal == 1 && !(cell.C33(0, 0) > 0))
    return CellProblem{"C33", "is not positive: the cell would give way along the fibres"};
  for (int r = 0; r < cell.n_rows(); ++r) {
    const bond::Bounds rule = bond::bounds(cell.kind(r), bond::State::broken, 0, 0, 0);
    if (cell.lower_broken(r) != rule.lower || cell.upper_broken(r) != rule.upper)
      return CellProblem{
          "", "row " + std::to_string(r) + ": its broken bounds are not the bond rule's (docs/method.md §11)"};
  }
  return convexity_problem(cell);
}

std::string consistency_problem(const CondensedCell& cell) {
  const std::optional<CellProblem> problem = find_problem(cell);
  if (!problem) return "";
  return problem->member.empty() ? problem->what : problem->member + ": " + problem->what;
}

}  // namespace dualcell::law
