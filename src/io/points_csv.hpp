#pragma once
// The points dualcell-law evaluates (docs/guide/evaluate.md): a CSV file, one state per row,
// three numbers (εxx, εyy, γxy) or (σxx, σyy, σxy), comma separated, with an optional header
// line and an optional first column `path`: rows with the same path value form one loading path,
// evaluated in file order from the unloaded state with the history carried along it. Blank lines
// and lines starting with # are skipped.
//
// The file is read a row at a time, never whole: a line is at most max_points_line bytes and the
// file at most max_points_bytes (checked before reading), so memory is bounded whatever the file.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/macro_state.hpp"

namespace dualcell::io {

// 1 GiB: about 30 million rows, hours of evaluation at the exact law's 0.02–100 ms per row.
inline constexpr std::uintmax_t max_points_bytes = std::uintmax_t{1} << 30;
// A row is three numbers and a path name: 4 KiB holds any of them.
inline constexpr std::size_t max_points_line = 4096;

struct LawPoint {
  std::string path;  // empty without the path column
  // The row's numbers in the law's order (core/macro_state.hpp): the in-plane three, then ε33
  // (a row of four or six) and γxz, γyz (a row of six), those held; strain-driven as read (the
  // stage says whether the in-plane part is a stress).
  MacroState state;
  long line = 0;  // the row's line in the file, for messages
};

class PointsReader {
 public:
  // An InputError naming the file when it is missing, not a regular file or beyond
  // max_points_bytes. `components`: the macro state's components a row gives, one number each in
  // the law's order (the in-plane three, always; ε33, γxz, γyz held where asked).
  explicit PointsReader(const std::filesystem::path& file, MacroState::Mask components = MacroState::in_plane_mask);
  // The next row into `point`; false after the last one. An InputError naming the file, the line
  // and what is wrong for a row that is not `numbers` (or, with a path first, one more) finite
  // numbers, a line beyond max_points_line, or a file without rows.
  bool next(LawPoint& point);
  bool has_path() const { return columns_ == numbers_ + 1; }
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  std::ifstream in_;
  std::vector<char> line_;
  long number_of_line_ = 0, rows_ = 0;
  std::vector<MacroState::Component> components_;
  int columns_ = 0, numbers_ = 3;
  bool first_row_ = true;
};

}  // namespace dualcell::io
