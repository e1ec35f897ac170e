#pragma once
// Disjoint sets of 0 … n−1 (union–find with path halving): which elements one relation joins
// into one piece, e.g. triangles sharing an edge, rows acting on one body, points tied together.
#include <numeric>
#include <vector>

namespace dualcell {

class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(static_cast<std::size_t>(n)) { std::iota(parent_.begin(), parent_.end(), 0); }
  // The representative of a's set.
  int find(int a) {
    while (parent_[static_cast<std::size_t>(a)] != a)
      a = parent_[static_cast<std::size_t>(a)] =
          parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(a)])];
    return a;
  }
  // Joins a's set into b's (b's representative stays).
  void join(int a, int b) { parent_[static_cast<std::size_t>(find(a))] = find(b); }

 private:
  std::vector<int> parent_;
};

}  // namespace dualcell
