// Value repeats (format-spec/geometry_section.md, "Value repeats"), the value repeats tool: a
// coordinate equal to a value already coded on its axis (CAD cages, symmetric and revolved shapes:
// OpenSubdiv's pawn repeats 77% of its coordinates) is coded as the rank of that value among the
// axis's distinct values, ordered by distance to the prediction (ties: the smaller value first), so a
// repeat costs the rank of the value among those about as close, usually 0 or 1.
#pragma once

#include <cstdint>
#include <vector>

#include "order_set.h"

namespace qsp {

// Decoder side: the values in order, in sorted blocks of at most kBlock (a std::set cost 2x the whole
// lossless decode of a 222k-vertex scan), the blocks in pages of at most kPage: with one flat list of
// blocks, every split moved all the blocks after it (16M distinct values inserted in descending order:
// 23 s; now 1.1 s).
class Repeats {
 public:
  static constexpr std::uint32_t kMaxRank = 63;  // 255 saved 0.1% more and walked 4x as far
  bool empty() const { return pages_.empty(); }
  // Adds v (nothing if it is there already).
  void insert(std::int64_t v);
  // The value of rank k from `pred` (distance to it, ties the smaller value first); false if there
  // are not that many.
  bool nth(std::int64_t pred, std::uint32_t k, std::int64_t& v) const;

 private:
  static constexpr std::size_t kBlock = 256, kPage = 256;
  struct Page {
    std::vector<std::vector<std::int64_t>> blocks;  // sorted, disjoint, in order; none empty
    std::vector<std::int64_t> last;                 // each block's largest value
  };
  struct Cursor {
    std::size_t page, block, index;
  };
  std::int64_t at(const Cursor& c, std::size_t index) const { return pages_[c.page].blocks[c.block][index]; }
  // The first page (block of `page`) whose last value is >= v (the count if none).
  std::size_t page_of(std::int64_t v) const {
    return static_cast<std::size_t>(std::lower_bound(page_last_.begin(), page_last_.end(), v) -
                                    page_last_.begin());
  }
  static std::size_t block_in(const Page& page, std::int64_t v) {
    return static_cast<std::size_t>(std::lower_bound(page.last.begin(), page.last.end(), v) -
                                    page.last.begin());
  }
  std::vector<Page> pages_;              // sorted, disjoint, in order; none empty
  std::vector<std::int64_t> page_last_;  // each page's largest value
};

// Encoder side: every value the axis will insert is known up front, so an order-statistic set over
// their sorted distinct list gives a rank in O(log n); walking the values would cost hundreds of steps
// per coordinate on dense axes (4-decimal scans).
class RepeatRanks {
 public:
  RepeatRanks() = default;
  // `values`: every value the axis will insert, in any order, repeats allowed.
  explicit RepeatRanks(std::vector<std::int64_t> values);
  bool empty() const { return set_.empty(); }
  // Where planned value v is kept, for rank_of and insert (one search for both); Error(kInternal) if
  // v is not one of the planned values.
  std::size_t slot(std::int64_t v) const;
  // Adds the value at `slot`.
  void insert(std::size_t slot);
  // The rank of v, the value at `slot`, from `pred` (values strictly closer, and as close but
  // smaller), or Repeats::kMaxRank + 1 if v is not in the set or ranks beyond that.
  std::uint32_t rank_of(std::int64_t pred, std::int64_t v, std::size_t slot) const;

 private:
  // Below this span of values a lookup table always serves index() (above it, when the span is under 4
  // values a vertex): binary searches over the distinct values were a tenth of compressing spot.
  static constexpr std::uint64_t kDenseAlways = std::uint64_t{1} << 16;
  std::size_t index(std::int64_t v) const;  // of the first planned value >= v
  std::int64_t min_ = 0, max_ = 0;          // the planned values' range
  std::vector<std::uint32_t> dense_;        // if not empty: per value min_ + k, index(min_ + k)
  std::vector<std::int64_t> sorted_;        // the planned values, distinct
  std::vector<std::uint8_t> in_;            // per planned value: inserted
  OrderSet set_;                            // indices into sorted_ of the values inserted
};

}  // namespace qsp
