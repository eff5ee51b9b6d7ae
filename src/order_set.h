// An order-statistic set over the integers 0 .. capacity - 1: insert, erase, rank (members below a
// value) and select (the member of a given rank) in O(log n), through a Fenwick tree of counts. The one
// copy of it in the library: canonical labelling (open darts), the topology coder's pool of darts
// without a predecessor, and the geometry encoder's ranks of repeated values use it. It keeps no
// membership flags (canonical labelling builds one per root tried): callers know what they inserted.
// It counts: a value inserted k times is k members (canonical labelling keeps one per open dart in
// each 64-dart word), erase removes one of them.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

namespace qsp {

class OrderSet {
 public:
  explicit OrderSet(std::size_t capacity = 0) : tree_(capacity, 0) {}

  std::size_t capacity() const { return tree_.size(); }
  std::uint32_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

  // Adds i (< capacity) once more.
  void insert(std::size_t i) {
    ++size_;
    for (std::size_t j = i + 1; j <= tree_.size(); j += j & (~j + 1)) ++tree_[j - 1];
  }
  // Removes member i (once).
  void erase(std::size_t i) {
    --size_;
    for (std::size_t j = i + 1; j <= tree_.size(); j += j & (~j + 1)) --tree_[j - 1];
  }
  // Members below i (i <= capacity).
  std::uint32_t rank(std::size_t i) const {
    std::uint32_t r = 0;
    for (std::size_t j = i; j > 0; j -= j & (~j + 1)) r += tree_[j - 1];
    return r;
  }
  // The member with `r` members below it; capacity() if there are not that many.
  std::size_t select(std::uint32_t r) const {
    std::size_t pos = 0;
    for (std::size_t step = std::bit_floor(tree_.size()); step > 0; step >>= 1) {
      if (pos + step <= tree_.size() && tree_[pos + step - 1] <= r) {
        pos += step;
        r -= tree_[pos - 1];
      }
    }
    return pos;
  }
  // Removes every member, keeping the capacity.
  void clear() {
    std::fill(tree_.begin(), tree_.end(), 0);
    size_ = 0;
  }
  // Grows the capacity to at least `need`: to 64, then by doubling, keeping the members. The capacity
  // stays a power of two, so the tree grows in place: the new nodes cover only the new, empty range,
  // but for the last, which covers everything.
  void reserve(std::size_t need) {
    if (need <= tree_.size()) return;
    std::size_t cap = tree_.empty() ? 64 : tree_.size();
    while (cap < need) cap *= 2;
    const std::size_t old = tree_.size();
    tree_.resize(cap, 0);
    for (std::size_t c = old ? old * 2 : cap; c <= cap; c *= 2) tree_[c - 1] = size_;
  }

 private:
  std::vector<std::uint32_t> tree_;  // tree_[j - 1]: members in (j - lowbit(j), j]
  std::uint32_t size_ = 0;
};

}  // namespace qsp
