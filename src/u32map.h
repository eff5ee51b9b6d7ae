// src/u32map.h (internal): an open-addressing map from uint32 keys to uint32 values.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "qsp/mesh.h"

namespace qsp::detail {

// Sized by what is inserted, never by the mesh, so a stage touches memory proportional to what it
// stores (the motorcycle graph's §5 sublinear construction, a partition's cut half-edges). Keys must
// not be kInvalid.
class U32Map {
 public:
  explicit U32Map(std::size_t expected) {
    std::size_t cap = 16;
    while (cap < 2 * expected) cap <<= 1;
    slots_.assign(cap, {kInvalid, 0});
  }
  const std::uint32_t* find(std::uint32_t key) const {
    for (std::size_t i = hash(key);; i = (i + 1) & (slots_.size() - 1)) {
      if (slots_[i].first == key) return &slots_[i].second;
      if (slots_[i].first == kInvalid) return nullptr;
    }
  }
  // Inserts key -> value unless key is present; returns true if inserted.
  bool insert(std::uint32_t key, std::uint32_t value) { return try_insert(key, value).second; }
  // The same, also returning the value now stored for key (`value` if inserted).
  std::pair<std::uint32_t, bool> try_insert(std::uint32_t key, std::uint32_t value) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    for (std::size_t i = hash(key);; i = (i + 1) & (slots_.size() - 1)) {
      if (slots_[i].first == key) return {slots_[i].second, false};
      if (slots_[i].first == kInvalid) {
        slots_[i] = {key, value};
        ++size_;
        return {value, true};
      }
    }
  }

 private:
  std::size_t hash(std::uint32_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 20) & (slots_.size() - 1);
  }
  void grow() {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> old;
    old.swap(slots_);
    slots_.assign(old.size() * 2, {kInvalid, 0});
    size_ = 0;
    for (const auto& s : old)
      if (s.first != kInvalid) insert(s.first, s.second);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> slots_;
  std::size_t size_ = 0;
};

}  // namespace qsp::detail
