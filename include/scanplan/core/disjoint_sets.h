#pragma once
// Disjoint sets of the indices 0..n-1 (union-find with path halving).

#include <numeric>
#include <vector>

namespace scanplan {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n = 0) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }

  std::size_t size() const { return parent_.size(); }

  // The root of the set of `v`.
  int find(int v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }

  // Puts the set of `from` into the set of `to`, whose root stays the root. False when they
  // were one set already.
  bool join(int from, int to) {
    const int a = find(from), b = find(to);
    if (a == b) return false;
    parent_[a] = b;
    return true;
  }

  // Adds the index size() as a set of its own.
  void add() { parent_.push_back(static_cast<int>(parent_.size())); }

  // Forgets the indices from `n` on, which no index below `n` may lie under.
  void truncate(std::size_t n) { parent_.resize(n); }

 private:
  std::vector<int> parent_;
};

}  // namespace scanplan
