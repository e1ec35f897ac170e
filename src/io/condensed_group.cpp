#include "io/condensed_group.hpp"

#include <algorithm>
#include <limits>
#include <string_view>
#include <type_traits>

#include "core/error.hpp"
#include "law/condensed_members.hpp"

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

}  // namespace

void write_condensed(File& f, const std::string& group, const law::CondensedCell& cell) {
  f.create_group(group);
  const auto dim = [&](law::Extent e) { return static_cast<hsize_t>(law::extent(cell, e)); };
  // Without an optional part (the strain along the fibres, the shear along them) its members are
  // left out (law::left_out).
  law::for_each_member(cell, [&](const law::Member& m, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const std::string name = group + "/" + m.name;
    if (law::left_out(cell, m)) return;
    if constexpr (law::CountMember<T>)
      f.write(name, std::vector<std::int64_t>{value}, {1});
    else if constexpr (law::RealMember<T>)
      f.write(name, std::vector<double>{value}, {1});
    else if constexpr (law::ArrayMember<T>)
      f.write(name, row_major(value),
              m.cols == law::Extent::one ? Shape{dim(m.rows)} : Shape{dim(m.rows), dim(m.cols)});
    else if constexpr (law::ListMember<T>)
      f.write(name, std::vector<std::int64_t>(value.begin(), value.end()), {dim(m.rows)});
  });
  // Derived, for the reader of the file: what the summaries print as the law's size.
  f.write(group + "/bytes", std::vector<std::int64_t>{static_cast<std::int64_t>(cell.bytes())}, {1});
}

law::CondensedCell read_condensed(const File& f, const std::string& group) {
  const auto fail = [&](const std::string& object, const std::string& what) {
    throw InputError(f.path().string() + ": " + object + ": " + what);
  };
  if (!f.exists(group)) fail(group, "missing group");
  law::CondensedCell cell;
  // Each extent as it becomes known (from a count, or from the first array that has it), and
  // the object it came from, for the message of an array that disagrees.
  hsize_t size[law::n_extents];
  std::fill(std::begin(size), std::end(size), any_extent);
  size[static_cast<std::size_t>(law::Extent::one)] = 1;
  std::string like[law::n_extents];
  const auto known = [&](law::Extent e, hsize_t found, const std::string& from) {
    const auto i = static_cast<std::size_t>(e);
    if (size[i] == any_extent) size[i] = found, like[i] = " like " + from;
  };
  // An array's declared shape against its extents' limits, before a byte of it is read: a file
  // declaring 40 000 rows would otherwise have H (12.8 GB) allocated before anything says no.
  const auto refuse_beyond_limits = [&](const std::string& name, const law::Member& m) {
    if (!f.exists(name)) return;  // the read says what is missing
    const Shape dims = f.shape(name);
    const law::Extent extents[2] = {m.rows, m.cols};
    for (std::size_t d = 0; d < dims.size() && d < 2; ++d)
      if (static_cast<long double>(dims[d]) > law::extent_limit(extents[d]))
        fail(name, "declares " + std::to_string(dims[d]) + " " + law::extent_name(extents[d]) + ", at most " +
                       std::to_string(law::extent_limit(extents[d])) + " (the largest cell the condensation forms)");
  };
  law::for_each_member(cell, [&](const law::Member& m, auto&& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const std::string name = group + "/" + m.name;
    const auto rows = static_cast<std::size_t>(m.rows), cols = static_cast<std::size_t>(m.cols);
    // An optional count an older file does not have is 0, and so is an array of its extent.
    if (m.optional && !f.exists(name)) {
      if constexpr (law::CountMember<T>) value = 0;
      known(m.sizes, 0, name);
      return;
    }
    if constexpr (law::ArrayMember<T>) {
      if ((law::optional_extent(m.rows) || law::optional_extent(m.cols)) && (size[rows] == 0 || size[cols] == 0) &&
          !f.exists(name)) {
        const auto empty_or = [&](hsize_t n) { return static_cast<Eigen::Index>(n == any_extent ? 0 : n); };
        value = Eigen::MatrixXd(empty_or(size[rows]), empty_or(size[cols]));
        return;
      }
    } else if constexpr (law::ListMember<T>) {
      if (law::optional_extent(m.rows) && size[rows] == 0 && !f.exists(name)) {
        value.clear();
        return;
      }
      // A file of the shear along the fibres written before pair_z had a shear row per pair, in
      // order: that is what its rows are.
      if (std::string_view(m.name) == "pair_z" && !f.exists(name) && size[rows] == static_cast<hsize_t>(cell.n_pairs)) {
        value.resize(static_cast<std::size_t>(cell.n_pairs));
        for (int p = 0; p < cell.n_pairs; ++p) value[static_cast<std::size_t>(p)] = p;
        return;
      }
    }
    if constexpr (law::CountMember<T>) {
      const std::int64_t v = f.read_ints(name, {1})[0];
      const std::int64_t lo = std::max<std::int64_t>(m.lo, std::numeric_limits<T>::min());
      const std::int64_t hi = std::min<std::int64_t>(m.hi, std::numeric_limits<T>::max());
      if (v < lo || v > hi)
        fail(name, std::to_string(v) + " is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
      value = static_cast<T>(v);
      if (m.sizes != law::Extent::one) known(m.sizes, static_cast<hsize_t>(v), name);
    } else if constexpr (law::RealMember<T>) {
      value = f.read_doubles(name, {1})[0];
    } else if constexpr (law::ArrayMember<T>) {
      refuse_beyond_limits(name, m);
      Shape found;
      const std::string why = like[rows].empty() ? like[cols] : like[rows];
      if (m.cols == law::Extent::one) {
        const auto v = f.read_doubles(name, {size[rows]}, why, &found);
        value = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
      } else {
        const auto v = f.read_doubles(name, {size[rows], size[cols]}, why, &found);
        value = from_row_major(v, found[0], found[1]);
      }
      known(m.rows, found[0], name);
    } else if constexpr (law::ListMember<T>) {
      refuse_beyond_limits(name, m);
      Shape found;
      for (const std::int64_t v : f.read_ints(name, {size[rows]}, like[rows], &found)) {
        using Entry = typename T::value_type;
        if (v < std::numeric_limits<Entry>::min() || v > std::numeric_limits<Entry>::max())
          fail(name, std::to_string(v) + " is not in [" + std::to_string(std::numeric_limits<Entry>::min()) + ", " +
                         std::to_string(std::numeric_limits<Entry>::max()) + "]");
        value.push_back(static_cast<Entry>(v));
      }
      known(m.rows, found[0], name);
    }
  });
  if (const auto problem = law::find_problem(cell))
    fail(problem->member.empty() ? group : group + "/" + problem->member, problem->what);
  return cell;
}

}  // namespace dualcell::io
