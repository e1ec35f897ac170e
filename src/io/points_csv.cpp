#include "io/points_csv.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "core/error.hpp"
#include "core/text.hpp"

namespace dualcell::io {

namespace {

std::string_view trimmed(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    out.push_back(
        trimmed(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return out;
    start = comma + 1;
  }
}

// A number as C and CSV files write it, a leading + allowed ("+0.001").
bool number(std::string_view text, double& value) {
  if (text.size() > 1 && text[0] == '+' && text[1] != '-' && text[1] != '+') text.remove_prefix(1);
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end && !text.empty();
}

}  // namespace

PointsReader::PointsReader(const std::filesystem::path& file, MacroState::Mask components)
    : file_(file), line_(max_points_line + 1) {
  if ((components & MacroState::in_plane_mask) != MacroState::in_plane_mask)
    throw std::logic_error("PointsReader: a row always gives the in-plane state");
  for (int k = 0; k < MacroState::count; ++k)
    if (components >> k & 1) components_.push_back(static_cast<MacroState::Component>(k));
  numbers_ = static_cast<int>(components_.size());
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status)) throw InputError(file.string() + ": no such file");
  if (!std::filesystem::is_regular_file(status)) throw InputError(file.string() + ": not a regular file");
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (!ec && bytes > max_points_bytes)
    throw InputError(file.string() + ": " + formatted("%.3g", static_cast<double>(bytes)) +
                     " bytes, more than the 1 GiB a points file may have (split it)");
  in_.open(file);
  if (!in_) throw InputError(file.string() + ": cannot read");
}

bool PointsReader::next(LawPoint& point) {
  for (;;) {
    in_.getline(line_.data(), static_cast<std::streamsize>(line_.size()));
    const std::streamsize got = in_.gcount();
    if (in_.fail() && !in_.eof() && got == static_cast<std::streamsize>(line_.size()) - 1)
      throw InputError(file_.string() + ":" + std::to_string(number_of_line_ + 1) + ": a line longer than " +
                       std::to_string(max_points_line) + " bytes");
    if (got == 0 && !in_) {
      if (rows_ == 0) throw InputError(file_.string() + ": no rows");
      return false;
    }
    ++number_of_line_;
    // gcount counts the newline that getline consumed; the text ends before it.
    std::string_view raw(line_.data(), static_cast<std::size_t>(got));
    if (!raw.empty() && raw.back() == '\0') raw.remove_suffix(1);
    const std::string_view text = trimmed(raw);
    if (text.empty() || text[0] == '#') continue;
    const std::vector<std::string_view> f = fields(text);
    const std::string where = file_.string() + ":" + std::to_string(number_of_line_) + ": ";
    double value = 0;
    if (first_row_) {
      first_row_ = false;
      // A header: none of its fields is a number; it names the columns.
      bool any_number = false;
      for (const std::string_view field : f) any_number = any_number || number(field, value);
      if (!any_number) {
        const int n = numbers_;
        if (static_cast<int>(f.size()) != n && static_cast<int>(f.size()) != n + 1)
          throw InputError(where + "a header of " + std::to_string(f.size()) + " columns, expected " +
                           std::to_string(n) + " or " + std::to_string(n + 1) + " (path first)");
        columns_ = static_cast<int>(f.size());
        if (columns_ == n + 1 && f[0] != "path")
          throw InputError(where + "a header of " + std::to_string(n + 1) + " columns must start with 'path', not '" +
                           clipped(std::string(f[0])) + "'");
        continue;
      }
    }
    if (columns_ == 0) columns_ = static_cast<int>(f.size());
    if (columns_ != numbers_ && columns_ != numbers_ + 1)
      throw InputError(where + std::to_string(f.size()) + " columns, expected " + std::to_string(numbers_) +
                       " numbers or a path and " + std::to_string(numbers_) + " numbers");
    if (static_cast<int>(f.size()) != columns_)
      throw InputError(where + std::to_string(f.size()) + " columns, expected " + std::to_string(columns_) +
                       " like the first row");
    point.state = MacroState::strain(Eigen::Vector3d::Zero());
    for (int k = 0; k < numbers_; ++k) {
      const std::string_view field = f[columns_ - numbers_ + k];
      double v = 0;
      if (!number(field, v) || !std::isfinite(v))
        throw InputError(where + "column " + std::to_string(columns_ - numbers_ + 1 + k) + " = '" +
                         clipped(std::string(field)) + "' is not a finite number");
      const MacroState::Component c = components_[static_cast<std::size_t>(k)];
      if (c < 3)
        point.state.value(c) = v;
      else
        point.state.hold(c, v);
    }
    point.path = has_path() ? std::string(f[0]) : std::string();
    point.line = number_of_line_;
    ++rows_;
    return true;
  }
}

}  // namespace dualcell::io
