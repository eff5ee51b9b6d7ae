// The geometry section's value domains (format-spec/geometry_section.md, "Values per axis",
// "Residuals"): each axis is coded as integers, either a quantized grid, a decimal grid (a file's
// numbers with k decimals, bit-exact) or the order-preserving image of the float bits; and the exact
// integer arithmetic the predictors share.
//
// Determinism: integer axes predict with integer arithmetic only. Float axes predict with additions in
// binary64 and one rounding to binary32, and dequantization multiplies by a step whose product is
// exact. So FMA contraction cannot change a result, and the decoder recomputes the encoder's
// predictions bit for bit on any IEEE-754 machine.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace qsp {

// ---- Exact integer helpers

inline std::int64_t floor_div(std::int64_t a, std::int64_t b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
inline __int128 floor_div128(__int128 a, __int128 b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
inline std::uint64_t zigzag64(std::int64_t r) {
  return (static_cast<std::uint64_t>(r) << 1) ^ static_cast<std::uint64_t>(r >> 63);
}
inline std::int64_t unzigzag64(std::uint64_t u) {
  return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
}
// A quantized residual modulo 2^bits (qmax = 2^bits - 1), taken in [-2^(bits-1), 2^(bits-1)).
inline std::int64_t wrapped(std::int64_t r, std::int64_t qmax) {
  r &= qmax;
  return r > qmax / 2 ? r - (qmax + 1) : r;
}

// ---- Float bits

// Order-preserving image of float bits: negative floats reversed below the positive ones.
inline std::uint32_t float_image(float f) {
  const std::uint32_t u = std::bit_cast<std::uint32_t>(f);
  return u ^ ((u >> 31) ? 0xFFFFFFFFu : 0x80000000u);
}
inline float image_float(std::uint32_t m) {
  return std::bit_cast<float>(m ^ ((m >> 31) ? 0x80000000u : 0xFFFFFFFFu));
}

// ---- Decimal grids: float = the binary32 nearest to n / 10^k (ties to even), exactly what
// std::from_chars gives for the decimal text.

inline constexpr int kMaxDecimals = 9;
inline constexpr std::int64_t kDecimalLimit = std::int64_t{1} << 40;  // |n| < 2^40
inline constexpr std::array<double, kMaxDecimals + 1> kPow10 = {1e0, 1e1, 1e2, 1e3, 1e4,
                                                                1e5, 1e6, 1e7, 1e8, 1e9};

// The exact rounding through text, for the rare midpoints decimal_float cannot settle.
float decimal_float_slow(std::int64_t n, int k);

// n / 10^k in binary64 is correctly rounded (both exact); rounding that to binary32 is then correct
// unless it landed exactly on a midpoint between two floats, which the slow path settles.
inline float decimal_float(std::int64_t n, int k) {
  const double d = static_cast<double>(n) / kPow10[static_cast<std::size_t>(k)];
  const float f = static_cast<float>(d);
  if (static_cast<double>(f) != d) {
    const float g = std::nextafter(
        f, d > f ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity());
    if ((static_cast<double>(f) + static_cast<double>(g)) * 0.5 == d) return decimal_float_slow(n, k);
  }
  return f;
}

// The decimal integer for x at k decimals, or false if x is not exactly such a value.
bool decimal_of(float x, int k, std::int64_t& n);

// The float a decimal-grid integer stands for (|n| < 2^40, 0 <= k <= 9; else Error(kUsage)).
float decimal_grid_value(std::int64_t n, int k);

inline std::int64_t clamp_decimal(std::int64_t p) {
  return std::clamp(p, -(kDecimalLimit - 1), kDecimalLimit - 1);
}

// Trailing-zero coding: n = m * 10^t, t at most 12 (10^12 < 2^40 < 10^13).
inline constexpr int kMaxTrailingZeros = 12;
inline constexpr std::array<std::int64_t, kMaxTrailingZeros + 1> kPow10i = {
    1,        10,        100,        1000,        10000,        100000,       1000000,
    10000000, 100000000, 1000000000, 10000000000, 100000000000, 1000000000000};

inline int trailing_zeros(std::int64_t n) {
  int t = 0;
  while (n != 0 && t < kMaxTrailingZeros && n % 10 == 0) n /= 10, ++t;
  return t;
}
inline int decimal_digits(std::int64_t n) {  // of |n|; 0 for 0
  int d = 0;
  for (std::uint64_t m = static_cast<std::uint64_t>(n < 0 ? -n : n); m != 0; m /= 10) ++d;
  return d;
}
// p / 10^t rounded half up, the prediction of m.
inline std::int64_t rounded_unit(std::int64_t p, int t) {
  const std::int64_t unit = kPow10i[static_cast<std::size_t>(t)];
  return floor_div(2 * p + unit, 2 * unit);
}

// ---- Axis descriptors (lossless)

inline constexpr std::uint8_t kFloatBits = 0;        // mode byte; 1 + k: decimal grid with k decimals
inline constexpr std::uint8_t kTrailingFlag = 0x80;  // in the mode byte: trailing-zero coding
inline constexpr int kFloatMaxLength = 33;           // zigzag of an image difference in (-2^32, 2^32)
inline constexpr int kDecimalMaxLength = 42;         // zigzag of n - clamp(prediction), both |.| < 2^40

struct Exception {
  std::uint32_t vertex;  // coding position
  float value;
};

struct AxisPlan {
  std::uint8_t mode = kFloatBits;
  bool trailing_zeros = false;  // decimal only: code each integer's trailing zero digits first
  std::vector<Exception> exceptions;
};

// The encoder's plan for axis `axis` of `positions` (3 floats a vertex): the cheapest decimal grid, or
// float bits, with its exceptions and whether trailing-zero coding pays.
AxisPlan plan_axis(std::span<const float> positions, int axis);

// ---- Quantization grid. step has at most 23 significant bits so q * step (q < 2^30) is exact in binary64.

inline constexpr std::uint64_t kStepLowMask =
    (std::uint64_t{1} << 30) - 1;  // fraction bits that must be zero

struct Grid {
  std::array<float, 3> origin{};
  double step = 0;
  float value(int axis, std::int64_t q) const {
    return static_cast<float>(static_cast<double>(origin[static_cast<std::size_t>(axis)]) +
                              static_cast<double>(q) * step);
  }
  // Nearest grid integer, clamped to the grid, and never one that decodes to infinity.
  std::int64_t quantize(int axis, float x, std::uint32_t bits) const {
    if (step == 0) return 0;
    std::int64_t q = nearest(axis, x, bits);
    while (q > 0 && !std::isfinite(value(axis, q))) --q;
    return q;
  }
  // Nearest grid integer, clamped to the grid (step > 0). The same as quantize() where the grid's top
  // point decodes finitely (all_finite): value() grows with q, so then every point does.
  std::int64_t nearest(int axis, float x, std::uint32_t bits) const {
    const double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
    return static_cast<std::int64_t>(
        std::clamp(std::nearbyint((double{x} - origin[static_cast<std::size_t>(axis)]) / step), 0.0, top));
  }
  bool all_finite(int axis, std::uint32_t bits) const {
    return step != 0 && std::isfinite(value(axis, static_cast<std::int64_t>((std::uint64_t{1} << bits) - 1)));
  }
};

// The grid over the bounding box's largest extent. Throws Error(kBadNumber) for a NaN or infinity.
Grid make_grid(std::span<const float> positions, std::uint32_t bits);

}  // namespace qsp
