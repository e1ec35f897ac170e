#include "io/condensed_group.hpp"

#include <limits>

#include "core/error.hpp"

namespace dualcell::io {

namespace {

std::vector<double> row_major(const Eigen::MatrixXd& M) {
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(M.size()));
  for (Eigen::Index i = 0; i < M.rows(); ++i)
    for (Eigen::Index j = 0; j < M.cols(); ++j) v.push_back(M(i, j));
  return v;
}

Eigen::MatrixXd from_row_major(const std::vector<double>& v, hsize_t rows, hsize_t cols) {
  Eigen::MatrixXd M(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  for (hsize_t i = 0; i < rows; ++i)
    for (hsize_t j = 0; j < cols; ++j) M(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = v[i * cols + j];
  return M;
}

std::vector<double> values(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

void write_condensed(File& f, const std::string& group, const law::CondensedCell& cell) {
  f.create_group(group);
  const auto n = static_cast<hsize_t>(cell.n_rows()), m = static_cast<hsize_t>(cell.n_macro);
  const auto count = [&](const std::string& name, std::int64_t value) {
    f.write(group + "/" + name, std::vector<std::int64_t>{value}, {1});
  };
  const auto scalar = [&](const std::string& name, double value) {
    f.write(group + "/" + name, std::vector<double>{value}, {1});
  };
  count("n_macro", cell.n_macro);
  count("n_pairs", cell.n_pairs);
  scalar("volume", cell.volume);
  scalar("reciprocity_error", cell.reciprocity_error);
  scalar("seconds", cell.seconds);
  count("operator_applications", cell.operator_applications);
  count("bytes", static_cast<std::int64_t>(cell.bytes()));
  f.write(group + "/S0", row_major(cell.S0), {m, m});
  f.write(group + "/Y", row_major(cell.Y), {n, m});
  f.write(group + "/H", row_major(cell.H), {n, n});
  f.write(group + "/G", row_major(cell.G), {static_cast<hsize_t>(cell.G.rows()), n});
  f.write(group + "/tangential", std::vector<std::int64_t>(cell.tangential.begin(), cell.tangential.end()), {n});
  f.write(group + "/pair", std::vector<std::int64_t>(cell.pair.begin(), cell.pair.end()), {n});
  f.write(group + "/lower_bonded", values(cell.lower_bonded), {n});
  f.write(group + "/upper_bonded", values(cell.upper_bonded), {n});
  f.write(group + "/lower_broken", values(cell.lower_broken), {n});
  f.write(group + "/upper_broken", values(cell.upper_broken), {n});
  f.write(group + "/bonded", std::vector<std::int64_t>(cell.bonded.begin(), cell.bonded.end()),
          {static_cast<hsize_t>(cell.n_pairs)});
}

law::CondensedCell read_condensed(const File& f, const std::string& group) {
  const auto fail = [&](const std::string& object, const std::string& what) {
    throw InputError(f.path().string() + ": " + object + ": " + what);
  };
  if (!f.exists(group)) fail(group, "missing group");
  const auto count = [&](const std::string& name, std::int64_t lo, std::int64_t hi) {
    const std::int64_t v = f.read_ints(group + "/" + name, {1})[0];
    if (v < lo || v > hi)
      fail(group + "/" + name,
           std::to_string(v) + " is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  };
  const auto scalar = [&](const std::string& name) { return f.read_doubles(group + "/" + name, {1})[0]; };
  law::CondensedCell cell;
  cell.n_macro = static_cast<int>(count("n_macro", 2, 3));
  cell.n_pairs = static_cast<int>(count("n_pairs", 0, std::numeric_limits<int>::max()));
  cell.volume = scalar("volume");
  cell.reciprocity_error = scalar("reciprocity_error");
  cell.seconds = scalar("seconds");
  cell.operator_applications = count("operator_applications", 0, std::numeric_limits<std::int64_t>::max());
  const auto m = static_cast<hsize_t>(cell.n_macro);
  Shape found;
  const auto Y = f.read_doubles(group + "/Y", {any_extent, m}, "", &found);
  const hsize_t n = found[0];
  const std::string like = " like " + group + "/Y";
  cell.Y = from_row_major(Y, n, m);
  cell.S0 = from_row_major(f.read_doubles(group + "/S0", {m, m}), m, m);
  cell.H = from_row_major(f.read_doubles(group + "/H", {n, n}, like), n, n);
  const auto G = f.read_doubles(group + "/G", {any_extent, n}, like, &found);
  cell.G = from_row_major(G, found[0], n);
  const auto ints = [&](const std::string& name, hsize_t size, const std::string& why) {
    return f.read_ints(group + "/" + name, {size}, why);
  };
  for (const std::int64_t t : ints("tangential", n, like)) {
    if (t != 0 && t != 1) fail(group + "/tangential", std::to_string(t) + " is not 0 or 1");
    cell.tangential.push_back(static_cast<std::uint8_t>(t));
  }
  for (const std::int64_t p : ints("pair", n, like)) {
    if (p < 0 || p >= cell.n_pairs) fail(group + "/pair", std::to_string(p) + " is not a pair index");
    cell.pair.push_back(static_cast<int>(p));
  }
  const auto vector = [&](const std::string& name) {
    const auto v = f.read_doubles(group + "/" + name, {n}, like);
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  };
  cell.lower_bonded = vector("lower_bonded");
  cell.upper_bonded = vector("upper_bonded");
  cell.lower_broken = vector("lower_broken");
  cell.upper_broken = vector("upper_broken");
  for (const std::int64_t b : ints("bonded", static_cast<hsize_t>(cell.n_pairs), " like " + group + "/n_pairs")) {
    if (b != 0 && b != 1) fail(group + "/bonded", std::to_string(b) + " is not 0 or 1");
    cell.bonded.push_back(static_cast<std::uint8_t>(b));
  }
  if (const std::string problem = law::consistency_problem(cell); !problem.empty()) fail(group, problem);
  return cell;
}

}  // namespace dualcell::io
