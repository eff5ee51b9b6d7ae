// The geometry section's value domains: see geometry_values.h. The encoder's choices here (decimal
// grid or float bits per axis, trailing-zero coding, the quantization grid) are heuristics; the
// decoder only reads what they wrote.
#include "geometry_values.h"

#include <charconv>
#include <string>

#include "qsp/error.h"

namespace qsp {
namespace {

// Trailing-zero coding pays when the zeros follow the magnitude, as with "%g" output (6 significant
// digits: 0.348799 and 0.0663178 share k = 7, but the first ends in a zero): estimate the cost of
// coding t given the digit count against the log2(10^t) bits it saves.
bool trailing_zeros_pay(std::span<const float> pos, int axis, int k) {
  std::array<std::array<double, kMaxTrailingZeros + 1>, 16> counts{};
  double saved = 0, total = 0;
  std::int64_t n;
  for (std::size_t i = static_cast<std::size_t>(axis); i < pos.size(); i += 3) {
    if (!decimal_of(pos[i], k, n)) continue;
    const int t = trailing_zeros(n);
    counts[static_cast<std::size_t>(std::min(decimal_digits(n), 15))][static_cast<std::size_t>(t)] += 1;
    saved += t * std::log2(10.0);
    total += 1;
  }
  double cost = 0;
  for (const auto& row : counts) {
    double sum = 0;
    for (double c : row) sum += c;
    for (double c : row)
      if (c > 0) cost -= c * std::log2(c / sum);
  }
  return saved > cost + 0.25 * total;
}

// Exceptions it would take to store axis `axis` at k decimals, stopping past `limit`.
std::size_t decimal_misses(std::span<const float> pos, int axis, int k, std::size_t limit) {
  std::size_t misses = 0;
  std::int64_t n;
  for (std::size_t i = static_cast<std::size_t>(axis); i < pos.size(); i += 3) {
    if (!decimal_of(pos[i], k, n) && ++misses > limit) break;
  }
  return misses;
}

}  // namespace

float decimal_float_slow(std::int64_t n, int k) {
  char buf[40];
  auto [end, ec] = std::to_chars(buf, buf + 30, n);
  (void)ec;
  *end++ = 'e';
  *end++ = '-';
  *end++ = static_cast<char>('0' + k);
  float f = 0;
  std::from_chars(buf, end, f);
  return f;
}

bool decimal_of(float x, int k, std::int64_t& n) {
  if (!std::isfinite(x)) return false;
  const double scaled = static_cast<double>(x) * kPow10[static_cast<std::size_t>(k)];
  if (!(std::fabs(scaled) < static_cast<double>(kDecimalLimit) - 1)) return false;
  n = std::llround(scaled);
  if (n == 0 && std::signbit(x)) return false;  // -0 has no decimal integer
  return std::bit_cast<std::uint32_t>(decimal_float(n, k)) == std::bit_cast<std::uint32_t>(x);
}

float decimal_grid_value(std::int64_t n, int k) {
  if (k < 0 || k > kMaxDecimals || n <= -kDecimalLimit || n >= kDecimalLimit) {
    throw Error(ErrorCode::kUsage,
                "decimal grid value out of range: n = " + std::to_string(n) + ", k = " + std::to_string(k));
  }
  return decimal_float(n, k);
}

// Cheapest decimal grid for the axis, or float bits. Estimates bits: a decimal step of 10^-k costs
// about log2(ulp(x) * 10^k) bits more per coordinate than the float's own ulp; a miss ~40 bits.
AxisPlan plan_axis(std::span<const float> pos, int axis) {
  const std::size_t count = pos.size() / 3;
  double log_ulp_sum = 0;  // sum of log2(ulp(x)) over finite x
  for (std::size_t i = static_cast<std::size_t>(axis); i < pos.size(); i += 3) {
    const float x = std::fabs(pos[i]);
    if (!std::isfinite(x)) continue;
    const int e = x < std::numeric_limits<float>::min() ? -126 : std::ilogb(x);
    log_ulp_sum += e - 23;
  }
  double best_cost = 0;  // float bits, relative
  int best_k = -1;
  for (int k = 0; k <= kMaxDecimals; ++k) {
    const double grid = static_cast<double>(count) * k * std::log2(10.0) + log_ulp_sum;  // bits vs float mode
    const double budget = (best_cost - grid) / 40.0;
    if (budget < 0) continue;
    const std::size_t misses = decimal_misses(pos, axis, k, static_cast<std::size_t>(budget));
    const double cost = grid + 40.0 * static_cast<double>(misses);
    if (cost < best_cost) {
      best_cost = cost;
      best_k = k;
    }
    if (misses == 0) break;  // more decimals only cost more
  }
  AxisPlan plan;
  if (best_k < 0) return plan;
  plan.mode = static_cast<std::uint8_t>(1 + best_k);
  plan.trailing_zeros = trailing_zeros_pay(pos, axis, best_k);
  std::int64_t n;
  for (std::uint32_t i = 0; i < count; ++i) {
    const float x = pos[3 * std::size_t{i} + static_cast<std::size_t>(axis)];
    if (!decimal_of(x, best_k, n)) plan.exceptions.push_back({i, x});
  }
  return plan;
}

Grid make_grid(std::span<const float> pos, std::uint32_t bits) {
  Grid g;
  double extent = 0;
  for (std::size_t a = 0; a < 3; ++a) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (std::size_t i = a; i < pos.size(); i += 3) {
      if (!std::isfinite(pos[i])) {
        throw Error(ErrorCode::kBadNumber, "geometry: cannot quantize a NaN or infinite coordinate");
      }
      lo = std::min(lo, pos[i]);
      hi = std::max(hi, pos[i]);
    }
    if (pos.empty()) lo = hi = 0;
    g.origin[a] = lo == 0 ? 0.0f : lo;  // no -0 origin: it adds nothing
    extent = std::max(extent, static_cast<double>(hi) - static_cast<double>(lo));
  }
  if (extent > 0) {
    const double ideal = extent / static_cast<double>((std::uint64_t{1} << bits) - 1);
    std::uint64_t b = std::bit_cast<std::uint64_t>(ideal);
    b = (b + kStepLowMask) & ~kStepLowMask;  // round up: keeps every q <= 2^bits - 1
    g.step = std::bit_cast<double>(b);
  }
  return g;
}

}  // namespace qsp
