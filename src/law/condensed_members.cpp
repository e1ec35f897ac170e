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
    case Extent::shear_rows:
    case Extent::shear_modes:
      return max_cell_rows;
    case Extent::longitudinal:
    case Extent::thermal:
      return 1;
    case Extent::shear:
      return 2;
  }
  return 0;
}

bool optional_extent(Extent e) {
  return e == Extent::longitudinal || e == Extent::shear || e == Extent::shear_rows || e == Extent::thermal;
}

bool of_shear(const Member& m) {
  for (const Extent e : {m.sizes, m.rows, m.cols})
    if (e == Extent::shear || e == Extent::shear_rows || e == Extent::shear_modes) return true;
  return false;
}

bool of_thermal(const Member& m) {
  for (const Extent e : {m.sizes, m.rows, m.cols})
    if (e == Extent::thermal) return true;
  return false;
}

bool left_out(const CondensedCell& cell, const Member& m) {
  for (const Extent e : {m.sizes, m.rows, m.cols})
    if (optional_extent(e) && extent(cell, e) == 0) return true;
  return false;
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
    case Extent::shear:
      return cell.shear;
    case Extent::shear_rows:
      return cell.shear_rows;
    case Extent::shear_modes:
      return cell.Gz.rows();
    case Extent::thermal:
      return cell.thermal;
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
    case Extent::shear:
      return "shear";
    case Extent::shear_rows:
      return "shear_rows";
    case Extent::shear_modes:
      return "shear_modes";
    case Extent::thermal:
      return "thermal";
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
      // G's and Gz's rows (fibre_modes, shear_modes) are their own, and without any their
      // columns do not matter.
      const bool free_rows = m.rows == Extent::fibre_modes || m.rows == Extent::shear_modes;
      // Without an optional part (its extent 0) its arrays may be empty of any shape.
      const bool none = left_out(cell, m) && rows * cols == 0;
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
      if (left_out(cell, m)) return;  // an optional part the cell does not have: empty
      if (m.values >= Values::finite && m.values <= Values::symmetric_positive_definite)
        finite = finite && value.allFinite();
      if ((m.values == Values::symmetric || m.values == Values::symmetric_positive_definite) && !symmetric(value)) {
        symmetric_names += (symmetric_names.empty() ? "" : " and ") + std::string(m.name);
        symmetric_all = false;
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
  if (!symmetric_all)
    return CellProblem{
        "", symmetric_names + (symmetric_names.find(" and ") == std::string::npos ? " is" : " are") + " not symmetric"};
  if (!not_definite.empty()) return CellProblem{"", not_definite + " is not positive definite"};
  return entry;
}

// Whether the symmetric positive semidefinite M is positive definite on the kernel of the rows
// C (acting on M's last C.cols() unknowns): M + CᵀC is factorised, equilibrated (M's diagonal
// scaled to 1, the rows of C to unit length), which is positive definite if and only if M is on
// ker C; an indefinite M fails either way. `what` names M in the message, `kernel` ker C.
std::optional<CellProblem> definite_problem(Eigen::MatrixXd M, const Eigen::MatrixXd& C, const std::string& what,
                                            const std::string& kernel) {
  const Eigen::Index N = M.rows(), n = C.cols();
  Eigen::VectorXd d(N);
  for (Eigen::Index i = 0; i < N; ++i) {
    if (!(M(i, i) > 0))
      return CellProblem{"", what + " has a diagonal entry ≤ 0 (row " + std::to_string(i) + "): the law is not convex"};
    d(i) = 1 / std::sqrt(M(i, i));
  }
  M = d.asDiagonal() * M * d.asDiagonal();
  if (C.rows() > 0) {
    Eigen::MatrixXd Cs = C * d.tail(n).asDiagonal();
    for (Eigen::Index g = 0; g < Cs.rows(); ++g)
      if (const double norm = Cs.row(g).norm(); norm > 0) Cs.row(g) /= norm;
    M.bottomRightCorner(n, n).noalias() += Cs.transpose() * Cs;
  }
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(M);
  const double smallest = llt.info() == Eigen::Success ? M.diagonal().cwiseAbs2().minCoeff() : 0.0;
  if (!(smallest >= pivot_floor(N)))
    return CellProblem{"", what + " is not positive definite on " + kernel + " (smallest equilibrated pivot " +
                               formatted("%.3g", smallest) + ", below " + formatted("%.3g", pivot_floor(N)) +
                               "): the law is not convex"};
  return std::nullopt;
}

// 𝓗 positive definite on the kernel of the fibres' rows [0 G]: the strain-driven law is then
// strictly convex on every admissible set, and each of its QPs has one solution; so is Hz on
// Gz q = 0, the longitudinal shear's.
std::optional<CellProblem> convexity_problem(const CondensedCell& cell) {
  if (auto problem = definite_problem(energy_matrix(cell), cell.G, "the energy [|Ω|S0 −Yᵀ; −Y H]", "G p = 0"))
    return problem;
  if (cell.shear_rows > 0) return definite_problem(cell.Hz, cell.Gz, "the shear rows' Hz", "Gz q = 0");
  return std::nullopt;
}

// The longitudinal shear's counts: 0 or 2 macro shears, rows only with the shears.
std::optional<CellProblem> shear_problem(const CondensedCell& cell) {
  if (cell.shear != 0 && cell.shear != 2)
    return CellProblem{"shear", "is " + std::to_string(cell.shear) + ", not 0 or 2"};
  if (cell.shear_rows > 0 && cell.shear == 0) return CellProblem{"shear_rows", "without the shears (shear = 0)"};
  return std::nullopt;
}

}  // namespace

std::optional<CellProblem> find_problem(const CondensedCell& cell) {
  if (auto problem = shear_problem(cell)) return problem;
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
