#pragma once
// The points dualcell-law evaluates (README, "dualcell-law"): a CSV file, one state per row,
// three numbers (εxx, εyy, γxy) or (σxx, σyy, σxy), comma separated, with an optional header
// line and an optional first column `path`: rows with the same path value form one loading path,
// evaluated in file order from the unloaded state with the history carried along it. Blank lines
// and lines starting with # are skipped.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace dualcell::io {

struct LawPoints {
  bool has_path = false;
  std::vector<std::string> path;  // per row (empty strings without the column)
  std::vector<Eigen::Vector3d> value;
  std::vector<int> line;  // the row's line in the file, for messages
};

// An InputError naming the file, the line and what is wrong for a row that is not 3 (or, with a
// path, 4) finite numbers, or a file without rows.
LawPoints read_points_csv(const std::filesystem::path& file);

}  // namespace dualcell::io
