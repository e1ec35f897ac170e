#include "law/cell_text.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <istream>
#include <limits>
#include <ostream>
#include <type_traits>

#include "law/condensed_members.hpp"

namespace dualcell::law {

namespace {

// 2: the strain along the fibres (longitudinal, A33, C33, y33); 4: the shear along them (shear …
// pair_z), written only by a cell that has it, so that a cell without it reads as before; 5: the
// temperature change too (thermal, AT, CT, yT, after the shear's members, which it writes with
// shear 0 where the cell has none), written only by a cell that has it. 3 was the shear with a
// row per pair (no pair_z): refused, the card is exported again.
constexpr const char* header = "dualcell cell law 2";
constexpr const char* header_shear = "dualcell cell law 4";
constexpr const char* header_thermal = "dualcell cell law 5";
constexpr const char* header_shear_3 = "dualcell cell law 3";

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

void write_values(std::ostream& out, const char* key, const double* v, Eigen::Index n) {
  out << key;
  for (Eigen::Index i = 0; i < n; ++i) out << ' ' << number(v[i]);
  out << '\n';
}

void write_matrix(std::ostream& out, const char* key, const Eigen::MatrixXd& M) {
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> R = M;
  write_values(out, key, R.data(), R.size());
}

template <class T>
void write_list(std::ostream& out, const char* key, const std::vector<T>& v) {
  out << key;
  for (const T& x : v) out << ' ' << static_cast<long>(x);
  out << '\n';
}

// Reads the keyword `key` and then n numbers; false (with `error`) when the text differs.
bool read_values(std::istream& in, const char* key, double* v, Eigen::Index n, std::string& error) {
  std::string word;
  if (!(in >> word) || word != key) {
    error = std::string("expected '") + key + "', found '" + word + "'";
    return false;
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(in >> word)) {
      error = std::string(key) + ": " + std::to_string(i) + " of " + std::to_string(n) + " numbers";
      return false;
    }
    char* end = nullptr;
    v[i] = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0') {
      error = std::string(key) + ": '" + word + "' is not a number";
      return false;
    }
  }
  return true;
}

bool read_matrix(std::istream& in, const char* key, Eigen::Index rows, Eigen::Index cols, Eigen::MatrixXd& M,
                 std::string& error) {
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> R(rows, cols);
  if (!read_values(in, key, R.data(), R.size(), error)) return false;
  M = R;
  return true;
}

template <class T>
bool read_list(std::istream& in, const char* key, Eigen::Index n, std::vector<T>& v, std::string& error) {
  Eigen::VectorXd values(n);
  if (!read_values(in, key, values.data(), n, error)) return false;
  v.resize(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lo = static_cast<double>(std::numeric_limits<T>::min());
    const double hi = static_cast<double>(std::numeric_limits<T>::max());
    if (values(i) != std::floor(values(i)) || !(values(i) >= lo && values(i) <= hi)) {
      error = std::string(key) + ": " + number(values(i)) + " is not an integer in [" + number(lo) + ", " + number(hi) +
              "]";
      return false;
    }
    v[static_cast<std::size_t>(i)] = static_cast<T>(values(i));
  }
  return true;
}

}  // namespace

void write_cell_text(std::ostream& out, const CondensedCell& cell) {
  const bool thermal = cell.thermal != 0, shear = cell.shear != 0 || thermal;
  out << (thermal ? header_thermal : shear ? header_shear : header) << '\n';
  for_each_member(cell, [&](const Member& m, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const char* key = m.text ? m.text : m.name;
    if (m.measured || (!shear && of_shear(m)) || (!thermal && of_thermal(m))) return;
    if constexpr (CountMember<T>)
      out << key << ' ' << value << '\n';
    else if constexpr (std::is_same_v<T, TextSize>)
      out << key << ' ' << extent(cell, m.sizes) << '\n';
    else if constexpr (RealMember<T>)
      out << key << ' ' << number(value) << '\n';
    else if constexpr (ArrayMember<T>)
      write_matrix(out, key, value);
    else if constexpr (ListMember<T>)
      write_list(out, key, value);
  });
}

std::uintmax_t max_cell_text_bytes() {
  // A number as number() prints it, sign, 17 digits, point and a three-digit exponent, and its
  // separator; a count or a list entry is shorter.
  constexpr std::uintmax_t number_bytes = 25;
  std::uintmax_t bytes = std::strlen(header_thermal) + 1;
  const CondensedCell cell;
  for_each_member(cell, [&](const Member& m, const auto&) {
    if (m.measured) return;
    const auto numbers = static_cast<std::uintmax_t>(extent_limit(m.rows) * extent_limit(m.cols));
    bytes += std::strlen(m.text ? m.text : m.name) + 1 + number_bytes * numbers;
  });
  return bytes;
}

CondensedCell read_cell_text(std::istream& in, std::string& error) {
  CondensedCell cell;
  std::string line;
  if (std::getline(in, line) && line == header_shear_3) {
    error = "'" + line +
            "': the shear along the fibres with a row per pair and no pair_z, an older layout: export the law again";
    return {};
  }
  if (!in || (line != header && line != header_shear && line != header_thermal)) {
    error = "the first line is not '" + std::string(header) + "', '" + header_shear + "' or '" + header_thermal + "'";
    return {};
  }
  const bool thermal = line == header_thermal, shear = line == header_shear || thermal;
  // The extents as the text states them, before the arrays.
  Eigen::Index size[n_extents] = {1};
  bool ok = true;
  for_each_member(cell, [&](const Member& m, auto&& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const char* key = m.text ? m.text : m.name;
    if (!ok || m.measured || (!shear && of_shear(m)) || (!thermal && of_thermal(m))) return;
    if constexpr (CountMember<T> || std::is_same_v<T, TextSize>) {
      double count = 0;
      ok = read_values(in, key, &count, 1, error);
      // The count's range before any array is allocated from it (rows: max_cell_rows).
      if (ok &&
          !(count >= static_cast<double>(m.lo) && count <= static_cast<double>(m.hi) && count == std::floor(count))) {
        error = std::string(key) + ": " + number(count) + " is not a count in [" + std::to_string(m.lo) + ", " +
                std::to_string(m.hi) + "]";
        ok = false;
      }
      if (m.sizes != Extent::one) size[static_cast<int>(m.sizes)] = static_cast<Eigen::Index>(count);
      if constexpr (CountMember<T>) value = static_cast<T>(count);
    } else if constexpr (RealMember<T>) {
      ok = read_values(in, key, &value, 1, error);
    } else if constexpr (ArrayMember<T>) {
      const Eigen::Index rows = size[static_cast<int>(m.rows)], cols = size[static_cast<int>(m.cols)];
      Eigen::MatrixXd M;
      ok = read_matrix(in, key, rows, cols, M, error);
      value = M;
    } else if constexpr (ListMember<T>) {
      ok = read_list(in, key, size[static_cast<int>(m.rows)], value, error);
    }
  });
  if (!ok) return {};
  std::string rest;
  if (in >> rest) {
    error = "'" + rest + "' after the last keyword";
    return {};
  }
  if (const std::string problem = consistency_problem(cell); !problem.empty()) {
    error = problem;
    return {};
  }
  return cell;
}

}  // namespace dualcell::law
