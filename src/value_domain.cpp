// The value domains' shared coding (value_domain.h).
#include "value_domain.h"

#include <algorithm>

namespace qsp {
namespace {
constexpr std::uint32_t kEscape = 0xFFFFFFFEu;
constexpr unsigned kWideHalf = 21;  // w < 2^42 follows an escape as two 21-bit halves
}  // namespace

bool quantize(std::span<float> values, unsigned K, unsigned c, std::uint32_t bits) {
  const double up = pow2(static_cast<int>(bits)), down = pow2(-static_cast<int>(bits));
  for (std::size_t i = c; i < values.size(); i += K)
    if (!(std::fabs(static_cast<double>(values[i]) * up) < static_cast<double>(kDecimalLimit - 1)))
      return false;
  for (std::size_t i = c; i < values.size(); i += K)
    values[i] = static_cast<float>(std::nearbyint(static_cast<double>(values[i]) * up) * down) +
                0.0f;  // -0 becomes 0, the grid's zero
  return true;
}

std::uint8_t choose_mode(std::span<const float> values, unsigned K, unsigned c, bool signed_zero) {
  for (int k = 0; k <= kMaxDecimals; ++k) {
    bool all = true;
    std::int64_t n = 0;
    for (std::size_t i = c; i < values.size() && all; i += K)
      all = (signed_zero && values[i] == 0) || decimal_of(values[i], k, n);
    if (all) return static_cast<std::uint8_t>(1 + k);
  }
  return kModeFloat;
}

void encode_residual(RangeEncoder& enc, IntModel& model, std::int64_t r) {
  const std::uint64_t z = zigzag64(r);
  model.encode(enc, static_cast<std::uint32_t>(std::min<std::uint64_t>(z, kEscape)));
  if (z < kEscape) return;
  const std::uint64_t w = z - kEscape;
  enc.encode_raw(static_cast<std::uint32_t>(w >> kWideHalf), kWideHalf);
  enc.encode_raw(static_cast<std::uint32_t>(w & ((1u << kWideHalf) - 1)), kWideHalf);
}

std::int64_t decode_residual(RangeDecoder& dec, IntModel& model) {
  std::uint64_t z = model.decode(dec);
  if (z == kEscape) {
    const std::uint64_t hi = dec.decode_raw(kWideHalf), lo = dec.decode_raw(kWideHalf);
    z += (hi << kWideHalf) | lo;
  }
  return unzigzag64(z);
}

}  // namespace qsp
