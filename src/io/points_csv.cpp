#include "io/points_csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <system_error>

#include "core/error.hpp"
#include "core/text.hpp"

namespace dualcell::io {

namespace {

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    out.push_back(trimmed(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

bool number(const std::string& text, double& value) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end && !text.empty();
}

}  // namespace

LawPoints read_points_csv(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw InputError(file.string() + ": not a regular file");
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot read");
  LawPoints points;
  std::string line;
  int number_of_line = 0, columns = 0;
  bool first_row = true;
  while (std::getline(in, line)) {
    ++number_of_line;
    const std::string text = trimmed(line);
    if (text.empty() || text[0] == '#') continue;
    const std::vector<std::string> f = fields(text);
    const std::string where = file.string() + ":" + std::to_string(number_of_line) + ": ";
    double value = 0;
    if (first_row) {
      first_row = false;
      // A header: none of its fields is a number; it names the columns.
      bool any_number = false;
      for (const std::string& field : f) any_number = any_number || number(field, value);
      if (!any_number) {
        if (f.size() != 3 && f.size() != 4)
          throw InputError(where + "a header of " + std::to_string(f.size()) +
                           " columns, expected 3 or 4 (path first)");
        columns = static_cast<int>(f.size());
        if (columns == 4 && f[0] != "path")
          throw InputError(where + "a header of 4 columns must start with 'path', not '" + clipped(f[0]) + "'");
        continue;
      }
    }
    if (columns == 0) columns = static_cast<int>(f.size());
    if (columns != 3 && columns != 4)
      throw InputError(where + std::to_string(f.size()) + " columns, expected 3 numbers or a path and 3 numbers");
    if (static_cast<int>(f.size()) != columns)
      throw InputError(where + std::to_string(f.size()) + " columns, expected " + std::to_string(columns) +
                       " like the first row");
    points.has_path = columns == 4;
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) {
      const std::string& field = f[columns - 3 + k];
      if (!number(field, v(k)) || !std::isfinite(v(k)))
        throw InputError(where + "column " + std::to_string(columns - 2 + k) + " = '" + clipped(field) +
                         "' is not a finite number");
    }
    points.path.push_back(columns == 4 ? f[0] : "");
    points.value.push_back(v);
    points.line.push_back(number_of_line);
  }
  if (points.value.empty()) throw InputError(file.string() + ": no rows");
  return points;
}

}  // namespace dualcell::io
