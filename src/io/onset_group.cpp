#include "io/onset_group.hpp"

#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace dualcell::io {

void write_onset(File& f, const std::string& group, const law::OnsetSurface& surface) {
  f.create_group(group);
  f.write_attribute(group, "linear", std::int64_t{surface.linear ? 1 : 0});
  f.write_attribute(group, "message", surface.message);
  const auto rows = [](const auto& matrix_rows, std::size_t n) {
    std::vector<double> v;
    v.reserve(3 * n);
    for (std::size_t k = 0; k < n; ++k)
      for (int j = 0; j < 3; ++j) v.push_back(matrix_rows(k, j));
    return v;
  };
  if (surface.linear) {
    const std::size_t K = surface.pair.size();
    f.write(group + "/facets",
            rows([&](std::size_t k, int j) { return surface.facets(static_cast<Eigen::Index>(k), j); }, K), {K, 3});
    f.write(group + "/pair", std::vector<std::int64_t>(surface.pair.begin(), surface.pair.end()), {K});
    f.write(group + "/tangential", std::vector<std::int64_t>(surface.tangential.begin(), surface.tangential.end()),
            {K});
  }
  if (!surface.path_stress.empty()) {
    const std::size_t P = surface.path_stress.size();
    f.write(group + "/path_stress", rows([&](std::size_t k, int j) { return surface.path_stress[k](j); }, P), {P, 3});
    f.write(group + "/onset", surface.path_onset, {P});
    f.write(group + "/sweep_onset", surface.path_sweep_onset, {P});
  }
}

law::OnsetSurface read_onset(const File& f, const std::string& group) {
  const auto fail = [&](const std::string& object, const std::string& what) {
    throw InputError(f.path().string() + ": " + object + ": " + what);
  };
  if (!f.exists(group)) fail(group, "missing group");
  law::OnsetSurface s;
  const std::int64_t linear = f.read_int_attribute_value(group, "linear");
  if (linear != 0 && linear != 1) fail(group, "attribute linear = " + std::to_string(linear) + ", not 0 or 1");
  s.linear = linear == 1;
  s.message = f.read_string_attribute(group, "message");
  if (s.linear) {
    Shape found;
    const auto g = f.read_doubles(group + "/facets", {any_extent, 3}, "", &found);
    const hsize_t K = found[0];
    s.facets.resize(static_cast<Eigen::Index>(K), 3);
    for (hsize_t k = 0; k < K; ++k)
      for (int j = 0; j < 3; ++j) {
        s.facets(static_cast<Eigen::Index>(k), j) = g[3 * k + j];
        if (!std::isfinite(g[3 * k + j])) fail(group + "/facets", "row " + std::to_string(k) + " is not finite");
      }
    const auto pair = f.read_ints(group + "/pair", {K}, " like " + group + "/facets");
    const auto tangential = f.read_ints(group + "/tangential", {K}, " like " + group + "/facets");
    for (hsize_t k = 0; k < K; ++k) {
      if (pair[k] < 0 || pair[k] > std::numeric_limits<int>::max())
        fail(group + "/pair", "entry " + std::to_string(k) + " = " + std::to_string(pair[k]) + " is not a pair index");
      if (tangential[k] != 0 && tangential[k] != 1)
        fail(group + "/tangential",
             "entry " + std::to_string(k) + " = " + std::to_string(tangential[k]) + ", not 0 or 1");
      s.pair.push_back(static_cast<int>(pair[k]));
      s.tangential.push_back(static_cast<int>(tangential[k]));
    }
  }
  if (f.exists(group + "/path_stress")) {
    Shape found;
    const auto N = f.read_doubles(group + "/path_stress", {any_extent, 3}, "", &found);
    const hsize_t P = found[0];
    for (hsize_t k = 0; k < P; ++k) s.path_stress.emplace_back(N[3 * k], N[3 * k + 1], N[3 * k + 2]);
    s.path_onset = f.read_doubles(group + "/onset", {P}, " like " + group + "/path_stress");
    s.path_sweep_onset = f.read_doubles(group + "/sweep_onset", {P}, " like " + group + "/path_stress");
  }
  return s;
}

}  // namespace dualcell::io
