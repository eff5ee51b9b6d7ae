// Value repeats: see geometry_repeats.h.
#include "geometry_repeats.h"

#include <algorithm>
#include <iterator>

#include "qsp/error.h"

namespace qsp {

void Repeats::insert(std::int64_t v) {
  if (pages_.empty()) {
    pages_.push_back({{{v}}, {v}});
    page_last_.push_back(v);
    return;
  }
  std::size_t p = page_of(v);
  if (p == pages_.size()) --p;  // beyond every page: append to the last
  Page& page = pages_[p];
  std::size_t b = block_in(page, v);
  if (b == page.blocks.size()) --b;
  std::vector<std::int64_t>& blk = page.blocks[b];
  auto it = std::lower_bound(blk.begin(), blk.end(), v);
  if (it != blk.end() && *it == v) return;
  blk.insert(it, v);
  page.last[b] = blk.back();
  if (blk.size() > kBlock) {  // split the block in two halves, within its page
    std::vector<std::int64_t> upper(blk.begin() + kBlock / 2, blk.end());
    blk.resize(kBlock / 2);
    page.last[b] = blk.back();
    page.last.insert(page.last.begin() + static_cast<std::ptrdiff_t>(b) + 1, upper.back());
    page.blocks.insert(page.blocks.begin() + static_cast<std::ptrdiff_t>(b) + 1, std::move(upper));
  }
  page_last_[p] = page.last.back();
  if (page.blocks.size() > kPage) {  // split the page in two halves
    Page upper;
    upper.blocks.assign(std::make_move_iterator(page.blocks.begin() + kPage / 2),
                        std::make_move_iterator(page.blocks.end()));
    upper.last.assign(page.last.begin() + kPage / 2, page.last.end());
    page.blocks.resize(kPage / 2);
    page.last.resize(kPage / 2);
    page_last_[p] = page.last.back();
    page_last_.insert(page_last_.begin() + static_cast<std::ptrdiff_t>(p) + 1, upper.last.back());
    pages_.insert(pages_.begin() + static_cast<std::ptrdiff_t>(p) + 1, std::move(upper));
  }
}

bool Repeats::nth(std::int64_t pred, std::uint32_t k, std::int64_t& v) const {
  // hi = first value >= pred, lo = the one before it, as (page, block, index) cursors; (pages, 0) is
  // the end.
  Cursor h{page_of(pred), 0, 0};
  if (h.page < pages_.size()) {
    const Page& page = pages_[h.page];
    h.block = block_in(page, pred);
    const auto& blk = page.blocks[h.block];
    h.index = static_cast<std::size_t>(std::lower_bound(blk.begin(), blk.end(), pred) - blk.begin());
  }
  Cursor l = h;  // its index points one past the next lower value
  for (std::uint32_t i = 0;; ++i) {
    while (l.index == 0 && (l.page > 0 || l.block > 0)) {
      if (l.block > 0) {
        --l.block;
      } else {
        --l.page;
        l.block = pages_[l.page].blocks.size() - 1;
      }
      l.index = pages_[l.page].blocks[l.block].size();
    }
    const bool has_lo = l.index > 0, has_hi = h.page < pages_.size();
    if (!has_lo && !has_hi) return false;
    bool take_lo = has_lo;
    if (has_lo && has_hi) take_lo = pred - at(l, l.index - 1) <= at(h, h.index) - pred;
    std::int64_t c;
    if (take_lo) {
      c = at(l, --l.index);
    } else {
      c = at(h, h.index++);
      if (h.index == pages_[h.page].blocks[h.block].size()) {
        h.index = 0;
        if (++h.block == pages_[h.page].blocks.size()) ++h.page, h.block = 0;
      }
    }
    if (i == k) {
      v = c;
      return true;
    }
  }
}

RepeatRanks::RepeatRanks(std::vector<std::int64_t> values) {
  if (!values.empty()) {
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    min_ = *lo, max_ = *hi;
  }
  const std::uint64_t span = static_cast<std::uint64_t>(max_) - static_cast<std::uint64_t>(min_);
  if (values.empty() || span >= std::max<std::uint64_t>(std::uint64_t{4} * values.size(), kDenseAlways)) {
    sorted_ = std::move(values);
    std::sort(sorted_.begin(), sorted_.end());
    sorted_.erase(std::unique(sorted_.begin(), sorted_.end()), sorted_.end());
  } else {
    // A narrow range (quantized coordinates): the values by presence, and every index by lookup.
    dense_.assign(span + 1, 0);
    for (std::int64_t v : values) dense_[static_cast<std::uint64_t>(v - min_)] = 1;
    std::uint32_t count = 0;
    for (std::uint64_t k = 0; k <= span; ++k) {
      const bool present = dense_[k] != 0;
      dense_[k] = count;  // planned values below min_ + k
      if (present) sorted_.push_back(min_ + static_cast<std::int64_t>(k)), ++count;
    }
  }
  in_.assign(sorted_.size(), 0);
  set_ = OrderSet(sorted_.size());
}

std::size_t RepeatRanks::index(std::int64_t v) const {
  if (dense_.empty())
    return static_cast<std::size_t>(std::lower_bound(sorted_.begin(), sorted_.end(), v) - sorted_.begin());
  if (v <= min_) return 0;
  if (v > max_) return sorted_.size();
  return dense_[static_cast<std::uint64_t>(v - min_)];
}

std::size_t RepeatRanks::slot(std::int64_t v) const {
  const std::size_t i = index(v);
  if (i == sorted_.size() || sorted_[i] != v)
    throw Error(ErrorCode::kInternal, "geometry: unplanned repeat value");
  return i;
}

void RepeatRanks::insert(std::size_t slot) {
  if (in_[slot]) return;
  in_[slot] = 1;
  set_.insert(slot);
}

std::uint32_t RepeatRanks::rank_of(std::int64_t pred, std::int64_t v, std::size_t slot) const {
  constexpr std::uint32_t kMiss = Repeats::kMaxRank + 1;
  if (!in_[slot]) return kMiss;
  const std::int64_t d = v >= pred ? v - pred : pred - v;
  if (d == 0) return 0;
  // Inserted values strictly closer than d: in (pred - d, pred + d). One end is v itself, at `slot`.
  const std::size_t lo = v < pred ? slot : index(pred - d);  // first planned value >= pred - d
  const std::size_t hi = v > pred ? slot : index(pred + d);
  const bool lo_planned = lo < sorted_.size() && sorted_[lo] == pred - d;
  std::size_t k = set_.rank(hi) - set_.rank(lo + (lo_planned ? 1 : 0));
  if (v > pred && lo_planned && in_[lo]) ++k;  // as close and smaller: it ranks first
  return static_cast<std::uint32_t>(std::min<std::size_t>(k, kMiss));
}

}  // namespace qsp
