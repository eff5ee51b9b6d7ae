// src/automorphisms.h (internal): what canonical.cpp uses to choose among many tied roots without a
// traversal each. A fan of n quads has n roots tied on topology; n traversals of O(n) darts took
// minutes at n = 40,000.
#pragma once

#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include "qsp/error.h"
#include "qsp/partition.h"

namespace qsp::detail {

// The positions i < n where a walk visiting darts dart(0), dart(1), ... first reaches each schematic
// vertex of `s`, in `out`: a relabelling by that walk numbers the vertices in this order (as
// schematic_from_next does) and lists them first in its layout. `seen`: scratch.
template <class DartAt>
void first_reached(const Schematic& s, std::uint32_t n, DartAt dart, std::vector<std::uint8_t>& seen,
                   std::vector<std::uint32_t>& out) {
  seen.assign(s.vertex_count, 0);
  out.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t v = s.dart_vertex[dart(i)];
    if (!seen[v]) seen[v] = 1, out.push_back(i);
  }
}

// The darts of the canonical traversal from a root in label order (as canonical.cpp's traverse labels
// them, without its code), made only as far as asked: choosing among tied roots by positions mostly
// reads a few darts of each.
class Walk {
 public:
  // Forgets the last walk (in the time it took) and starts one from `root`.
  void start(const Schematic& s, std::uint32_t root) {
    for (std::uint32_t i = 0; i < labelled_; ++i) label_[order_[i]] = kInvalid;
    if (label_.size() != s.dart_count())
      label_.assign(s.dart_count(), kInvalid), order_.resize(s.dart_count());
    next_ = s.dart_next.data();
    labelled_ = done_ = 0;
    assign(root);
  }
  // The dart labelled i (< the dart count; the schematic is connected).
  std::uint32_t at(std::uint32_t i) {
    while (labelled_ <= i) {
      if (done_ == labelled_) throw Error(ErrorCode::kInternal, "canonical: schematic is not connected");
      const std::uint32_t n = next_[order_[done_++]];
      if (label_[n] == kInvalid) assign(n);
    }
    return order_[i];
  }

 private:
  void assign(std::uint32_t d) {  // labels the edge of d, d first
    label_[d] = labelled_;
    label_[d ^ 1] = labelled_ + 1;
    order_[labelled_++] = d;
    order_[labelled_++] = d ^ 1;
  }
  const std::uint32_t* next_ = nullptr;
  std::vector<std::uint32_t> label_;       // per dart: its label, kInvalid if not yet reached
  std::vector<std::uint32_t> order_;       // darts in label order, the first labelled_ of them
  std::uint32_t labelled_ = 0, done_ = 0;  // darts labelled; darts whose next has been looked at
};

// The orbits of the darts under the automorphisms found so far (a union-find). An orientation-preserving
// automorphism is fixed by one dart's image, so two roots with equal codes give one, and every root in
// a tied root's orbit has that root's code. Each automorphism not yet in the group at least doubles it,
// so a component's roots cost O(darts log darts) here.
class Orbits {
 public:
  bool empty() const { return parent_.empty(); }
  // Whether darts x and y are known to lie in one orbit.
  bool same(std::uint32_t x, std::uint32_t y) { return !empty() && find(x) == find(y); }
  // Adds the automorphism taking a's traversal to `image`, a whole traversal of the same code, label for
  // label (image[i] is a.at(i)'s image).
  void add(Walk& a, const std::vector<std::uint32_t>& image) {
    const auto darts = static_cast<std::uint32_t>(image.size());
    if (empty()) {
      parent_.resize(darts);
      std::iota(parent_.begin(), parent_.end(), 0u);
      size_.assign(darts, 1);
    }
    for (std::uint32_t i = 0; i < darts; ++i) unite(a.at(i), image[i]);
  }

 private:
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];  // path halving
    return x;
  }
  void unite(std::uint32_t x, std::uint32_t y) {
    x = find(x), y = find(y);
    if (x == y) return;
    if (size_[x] < size_[y]) std::swap(x, y);
    parent_[y] = x;
    size_[x] += size_[y];
  }
  std::vector<std::uint32_t> parent_, size_;
};

}  // namespace qsp::detail
