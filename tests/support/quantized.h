// What a quantized decode may differ from its input by, worked out from the README's definition of
// the grid rather than from the encoder's code.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

namespace qsp::testing {

// The largest coordinate error `--quantize bits` may introduce on these positions: half a step of a
// uniform grid of 2^bits - 1 steps over the bounding box's largest extent (the encoder rounds the step
// up to 23 significant bits, at most 2^-22 relative), plus the rounding of the decoded float.
inline double quantization_bound(std::span<const float> positions, std::uint32_t bits) {
  double extent = 0, largest = 0;
  for (int a = 0; a < 3; ++a) {
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = a; i < positions.size(); i += 3) {
      lo = std::min(lo, double{positions[i]});
      hi = std::max(hi, double{positions[i]});
      largest = std::max(largest, std::abs(double{positions[i]}));
    }
    if (hi > lo) extent = std::max(extent, hi - lo);
  }
  const double half_step = 0.5 * extent / double((std::uint64_t{1} << bits) - 1) * (1 + 0x1p-21);
  return half_step + (largest + extent) * 0x1p-23;
}

}  // namespace qsp::testing
