#include "law/condensed_members.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace dualcell::law {

namespace {

bool symmetric(const Eigen::MatrixXd& M) {
  return M.rows() == M.cols() && (M - M.transpose()).norm() <= 1e-12 * std::max(M.norm(), 1e-300);
}

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
    } else if constexpr (ArrayMember<T> || ListMember<T>) {
      long rows = static_cast<long>(value.size()), cols = 1;
      if constexpr (ArrayMember<T>) rows = value.rows(), cols = value.cols();
      // G's rows (fibre_modes) are its own, and without any its columns do not matter.
      const bool free_rows = m.rows == Extent::fibre_modes;
      const bool shaped =
          (free_rows || rows == extent(cell, m.rows)) && (cols == extent(cell, m.cols) || (free_rows && rows == 0));
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

}  // namespace

std::optional<CellProblem> find_problem(const CondensedCell& cell) {
  if (auto problem = size_problem(cell)) return problem;
  if (auto problem = value_problem(cell)) return problem;
  for (int r = 0; r < cell.n_rows(); ++r) {
    const bond::Bounds rule = bond::bounds(cell.kind(r), bond::State::broken, 0, 0, 0);
    if (cell.lower_broken(r) != rule.lower || cell.upper_broken(r) != rule.upper)
      return CellProblem{
          "", "row " + std::to_string(r) + ": its broken bounds are not the bond rule's (docs/method.md §11)"};
  }
  return std::nullopt;
}

std::string consistency_problem(const CondensedCell& cell) {
  const std::optional<CellProblem> problem = find_problem(cell);
  if (!problem) return "";
  return problem->member.empty() ? problem->what : problem->member + ": " + problem->what;
}

}  // namespace dualcell::law
