#include "law/cell_text.hpp"

#include <cmath>
#include <cstdio>
#include <istream>
#include <limits>
#include <ostream>

namespace dualcell::law {

namespace {

constexpr const char* header = "dualcell cell law 1";

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
  out << header << '\n';
  out << "n_macro " << cell.n_macro << '\n';
  out << "volume " << number(cell.volume) << '\n';
  out << "rows " << cell.n_rows() << '\n';
  out << "pairs " << cell.n_pairs << '\n';
  out << "fibre_modes " << cell.G.rows() << '\n';
  write_matrix(out, "S0", cell.S0);
  write_matrix(out, "Y", cell.Y);
  write_matrix(out, "H", cell.H);
  write_matrix(out, "G", cell.G);
  write_list(out, "tangential", cell.tangential);
  write_list(out, "pair", cell.pair);
  write_values(out, "lower_bonded", cell.lower_bonded.data(), cell.lower_bonded.size());
  write_values(out, "upper_bonded", cell.upper_bonded.data(), cell.upper_bonded.size());
  write_values(out, "lower_broken", cell.lower_broken.data(), cell.lower_broken.size());
  write_values(out, "upper_broken", cell.upper_broken.data(), cell.upper_broken.size());
  write_list(out, "bonded", cell.bonded);
}

CondensedCell read_cell_text(std::istream& in, std::string& error) {
  CondensedCell cell;
  std::string line;
  if (!std::getline(in, line) || line != header) {
    error = "the first line is not '" + std::string(header) + "'";
    return {};
  }
  double sizes[5];
  const char* keys[5] = {"n_macro", "volume", "rows", "pairs", "fibre_modes"};
  for (int k = 0; k < 5; ++k)
    if (!read_values(in, keys[k], &sizes[k], 1, error)) return {};
  for (int k : {0, 2, 3, 4})
    if (!(sizes[k] >= 0 && sizes[k] <= 1e6 && sizes[k] == std::floor(sizes[k]))) {
      error = std::string(keys[k]) + ": " + number(sizes[k]) + " is not a count in [0, 1e6]";
      return {};
    }
  cell.n_macro = static_cast<int>(sizes[0]);
  cell.volume = sizes[1];
  const Eigen::Index m = cell.n_macro, n = static_cast<Eigen::Index>(sizes[2]), k = static_cast<Eigen::Index>(sizes[4]);
  cell.n_pairs = static_cast<int>(sizes[3]);
  cell.lower_bonded.resize(n), cell.upper_bonded.resize(n), cell.lower_broken.resize(n), cell.upper_broken.resize(n);
  if (!read_matrix(in, "S0", m, m, cell.S0, error) || !read_matrix(in, "Y", n, m, cell.Y, error) ||
      !read_matrix(in, "H", n, n, cell.H, error) || !read_matrix(in, "G", k, n, cell.G, error) ||
      !read_list(in, "tangential", n, cell.tangential, error) || !read_list(in, "pair", n, cell.pair, error) ||
      !read_values(in, "lower_bonded", cell.lower_bonded.data(), n, error) ||
      !read_values(in, "upper_bonded", cell.upper_bonded.data(), n, error) ||
      !read_values(in, "lower_broken", cell.lower_broken.data(), n, error) ||
      !read_values(in, "upper_broken", cell.upper_broken.data(), n, error) ||
      !read_list(in, "bonded", cell.n_pairs, cell.bonded, error))
    return {};
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
