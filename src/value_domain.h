// How a section of attribute values (texture coordinates, normals, colours) codes one component as
// integers (format-spec/qsp_format.md, "Texture coordinates section", *Integers*): a decimal grid of k
// decimals, a binary grid of step 2^-b, or the order-preserving image of the float bits; and the
// residual coding those sections share.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>

#include "entropy.h"
#include "geometry_values.h"

namespace qsp {

inline constexpr std::uint8_t kModeFloat = 0;  // 1 + k: decimal grid of k decimals; kModeGrid + b: step 2^-b
inline constexpr std::uint8_t kModeGrid = 0x10;
inline constexpr std::uint32_t kMaxGridBits = 24;

// 2^e for e in [-1022, 1023], built from its bits: x * pow2(e) is ldexp(x, e) exactly (one rounding,
// the same), without a library call per value (3% of compressing a mesh with UVs).
inline double pow2(int e) { return std::bit_cast<double>(static_cast<std::uint64_t>(1023 + e) << 52); }

// Whether a mode byte names a mode (0 to 10, or 17 to 40).
inline bool valid_mode(std::uint8_t mode) {
  return mode <= 1 + kMaxDecimals || (mode > kModeGrid && mode <= kModeGrid + kMaxGridBits);
}

// One component's domain: decimal integers (k decimals), integers on a grid of step 2^-b, or float
// images.
struct Domain {
  std::uint8_t mode = kModeFloat;
  bool grid() const { return mode > kModeGrid; }
  // The integer a value stands for (exact for the values the encoder writes).
  std::int64_t integer(float x) const {
    if (mode == kModeFloat) return float_image(x);
    if (grid()) return std::llround(static_cast<double>(x) * pow2(mode - kModeGrid));
    return std::llround(static_cast<double>(x) * kPow10[mode - 1u]);
  }
  // The value an integer stands for (|n| < 2^40, or a float image).
  float value(std::int64_t n) const {
    if (mode == kModeFloat) return image_float(static_cast<std::uint32_t>(n));
    if (grid()) return static_cast<float>(static_cast<double>(n) * pow2(kModeGrid - mode));
    return decimal_grid_value(n, mode - 1);
  }
  // Whether a decoded integer is in the domain's range: an image in [0, 2^32), a grid integer in
  // (-2^40, 2^40).
  bool holds(std::int64_t n) const {
    return mode == kModeFloat ? n >= 0 && n <= std::int64_t{0xFFFFFFFF}
                              : n > -kDecimalLimit && n < kDecimalLimit;
  }
  // A prediction clamped to the domain's range, so a residual stays below 2^41 in magnitude.
  std::int64_t clamp(std::int64_t p) const {
    return mode == kModeFloat ? std::clamp<std::int64_t>(p, 0, 0xFFFFFFFF) : clamp_decimal(p);
  }
  // The integer nearest a binary64 value: rounded half away from zero on a grid (the binary64 product
  // by 10^k or 2^b first), the image of its binary32 nearest (ties to even) in float bits.
  std::int64_t nearest(double x) const {
    if (mode == kModeFloat) return float_image(static_cast<float>(x));
    const double scaled = grid() ? x * pow2(mode - kModeGrid) : x * kPow10[mode - 1u];
    if (!(std::fabs(scaled) < static_cast<double>(kDecimalLimit - 1))) return 0;
    return clamp_decimal(static_cast<std::int64_t>(std::round(scaled)));
  }
  // The prediction with no term: 0, or the image of +0.0.
  std::int64_t none() const { return mode == kModeFloat ? float_image(0.0f) : 0; }
};

// Component c (of K per value) rounded to the grid of step 2^-bits (kept as it is, and false, if one of
// its values is too large for it: |x| * 2^bits must stay below 2^40).
bool quantize(std::span<float> values, unsigned K, unsigned c, std::uint32_t bits);

// The mode of the fewest decimals every value of component c is exactly on, or float bits; with
// `signed_zero` a -0 counts as on every grid (its sign coded apart).
std::uint8_t choose_mode(std::span<const float> values, unsigned K, unsigned c, bool signed_zero = false);

// A residual as zigzag(r) through `model` (min(z, 2^32 - 2)), then 21 + 21 raw bits beyond.
void encode_residual(RangeEncoder& enc, IntModel& model, std::int64_t r);
std::int64_t decode_residual(RangeDecoder& dec, IntModel& model);

}  // namespace qsp
