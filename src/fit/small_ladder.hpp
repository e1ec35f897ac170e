#pragma once
// Which small cell a law gets (docs/method.md §16c, §16d): the ladder of m = 8, 16, 24, 32 rows
// over the exact law's sample, or over full solves above its reach, each rung a
// fit_small_cell (fit/small_cell.hpp); with adhesion the small cell with a fuse
// (law/fused_cell.hpp), its part past the fuse climbed the same way over the exact law's cascade
// paths. Each writes law.small with its error on directions it was not fitted to, or
// law.small_note saying why there is none.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "fit/small_cell.hpp"
#include "law/cone_check.hpp"
#include "law/law.hpp"

namespace dualcell::fit {

// The directions of the exact law a small cell is fitted at (law::sample_cell; none of the
// check's), and past the fuse the cascade paths' directions counting their images under the
// cell's symmetries.
constexpr int small_cell_directions = 1500;
constexpr std::array<int, 4> small_cell_rows = {8, 16, 24, 32};

// How a ladder climbs: each rung continued from the last or from the greedy alone, up to how
// many rows, with how many of Lawson's rounds per rung.
struct Ladder {
  bool continued = true;
  int max_rows = small_cell_rows.back();
  int minimax_rounds = SmallCellOptions{}.minimax_rounds;
};

// The ladder of m over `training`, from `cell` (the exact law, or the cell on a basis of its own
// solutions with `start_sample` its own sample), measured on `check` (`against` says what that
// is); `tolerance` is the largest stress error the law promises (--law-tolerance).
void fit_small_ladder(law::Law& law, const law::CondensedCell& cell, const law::CellSample& training,
                      const law::CellSample* start_sample, const law::CellSample& check, law::CheckedAgainst against,
                      double tolerance, const Ladder& ladder = {}, Progress* progress = nullptr);

// The small cell of law.cell, the exact law: none for a cell of at most twice the largest m rows
// (it costs what a small cell would); without adhesion the ladder over the exact law's sample,
// measured on `check`; with adhesion the small cell with a fuse, fitted to the cascade paths
// `past_fuse_paths` with their images under the cell's symmetries `group` and measured along
// `past_fuse` (both null where the bonded law is not linear below its onset: then none).
void fit_small(law::Law& law, const law::CellSample& check, const law::CellSample* past_fuse,
               const law::CellSample* past_fuse_paths, const std::vector<Eigen::Matrix3d>& group, double tolerance,
               Progress* progress = nullptr);

}  // namespace dualcell::fit
