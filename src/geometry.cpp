// Geometry coding: per-vertex prediction from grid neighbours, residuals through an adaptive binary
// range coder. The byte layout is specified in format-spec/geometry_section.md; keep them in sync.
//
// Determinism: every float prediction is additions (and exact doublings) in binary64, then one
// rounding to binary32, and dequantization multiplies by a step whose product is exact. So FMA
// contraction cannot change a result and the decoder recomputes the encoder's predictions bit for bit.
#include "qsp/geometry.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "qsp/error.h"

namespace qsp {
namespace {

[[noreturn]] void fail(const char* what) { throw Error(ErrorCode::kFormat, std::string("geometry: ") + what); }

// ---------------------------------------------------------------------------------------------
// Bytes

void put_u8(std::string& out, std::uint8_t v) { out.push_back(static_cast<char>(v)); }

void put_varint(std::string& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>((v & 0x7F) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}

void put_le(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  std::size_t left() const { return bytes_.size() - pos_; }
  std::size_t pos() const { return pos_; }

  std::uint8_t u8(const char* what) {
    if (left() < 1) fail(what);
    return static_cast<std::uint8_t>(bytes_[pos_++]);
  }
  std::uint64_t le(int n, const char* what) {
    if (left() < static_cast<std::size_t>(n)) fail(what);
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t{static_cast<std::uint8_t>(bytes_[pos_++])} << (8 * i);
    return v;
  }
  // LEB128, at most 64 bits, minimal length (a unique encoding keeps corruption detectable).
  std::uint64_t varint(const char* what) {
    std::uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      const std::uint8_t b = u8(what);
      if (shift == 63 && b > 1) fail(what);
      v |= std::uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) {
        if (b == 0 && shift > 0) fail(what);
        return v;
      }
    }
  }
  std::string_view take(std::size_t n, const char* what) {
    if (left() < n) fail(what);
    std::string_view s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Binary range coder (LZMA style carry handling) with adaptive probabilities.

// P(bit = 0) in 1/65536 units, mixed from a fast and a slow estimate: quick to learn on small
// meshes, precise on large ones.
struct Prob {
  std::uint16_t fast = 32768, slow = 32768;
  std::uint32_t p0() const { return (std::uint32_t{fast} + slow) >> 1; }
  void update(int bit) {
    if (bit) {
      fast -= fast >> 4;
      slow -= slow >> 7;
    } else {
      fast += (65536 - fast) >> 4;
      slow += (65536 - slow) >> 7;
    }
  }
};

class RangeEncoder {
 public:
  void bit(Prob& p, int b) {
    const std::uint32_t bound = (range_ >> 16) * p.p0();
    if (b) {
      low_ += bound;
      range_ -= bound;
    } else {
      range_ = bound;
    }
    p.update(b);
    normalize();
  }
  void direct(std::uint64_t v, int n) {  // n raw bits, most significant first
    for (int i = n - 1; i >= 0; --i) {
      range_ >>= 1;
      if ((v >> i) & 1) low_ += range_;
      normalize();
    }
  }
  std::string finish() {
    for (int i = 0; i < 5; ++i) shift_low();
    return std::move(out_);
  }

 private:
  void normalize() {
    while (range_ < (1u << 24)) {
      range_ <<= 8;
      shift_low();
    }
  }
  void shift_low() {
    if (static_cast<std::uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
      const auto carry = static_cast<std::uint8_t>(low_ >> 32);
      std::uint8_t temp = cache_;
      do {
        out_.push_back(static_cast<char>(static_cast<std::uint8_t>(temp + carry)));
        temp = 0xFF;
      } while (--cache_size_ != 0);
      cache_ = static_cast<std::uint8_t>(low_ >> 24);
    }
    ++cache_size_;
    low_ = (low_ & 0x00FFFFFFu) << 8;
  }

  std::uint64_t low_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint8_t cache_ = 0;
  std::uint64_t cache_size_ = 1;
  std::string out_;
};

// Reads past the end as zero bytes but remembers it: a valid stream never does, so finish() refuses.
class RangeDecoder {
 public:
  explicit RangeDecoder(std::string_view bytes) : bytes_(bytes) {
    if (next() != 0) fail("range coder stream must start with a zero byte");
    for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next();
  }
  int bit(Prob& p) {
    const std::uint32_t bound = (range_ >> 16) * p.p0();
    int b;
    if (code_ < bound) {
      range_ = bound;
      b = 0;
    } else {
      code_ -= bound;
      range_ -= bound;
      b = 1;
    }
    p.update(b);
    normalize();
    return b;
  }
  std::uint64_t direct(int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) {
      range_ >>= 1;
      int b = 0;
      if (code_ >= range_) {
        code_ -= range_;
        b = 1;
      }
      v = (v << 1) | static_cast<std::uint64_t>(b);
      normalize();
    }
    return v;
  }
  // The encoder flushes exactly the bytes the decoder reads: anything else is corruption.
  void finish() const {
    if (pos_ != bytes_.size()) fail("range coder stream length mismatch");
  }
  bool overrun() const { return pos_ > bytes_.size(); }

 private:
  std::uint32_t next() {
    const std::uint32_t b = pos_ < bytes_.size() ? static_cast<std::uint8_t>(bytes_[pos_]) : 0;
    ++pos_;
    return b;
  }
  void normalize() {
    while (range_ < (1u << 24)) {
      range_ <<= 8;
      code_ = (code_ << 8) | next();
    }
  }

  std::string_view bytes_;
  std::size_t pos_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint32_t code_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Residual model: zigzag value u, coded as its bit length L (6-bit binary tree) and then the bits
// below the leading one (the first two with adaptive contexts, the rest raw).

constexpr int kKinds = 5;        // predictor kinds, see Predictor
constexpr int kBuckets = 24;     // neighbourhood magnitude classes
constexpr int kMaxLength = 63;   // a 6-bit tree
constexpr int kModelledBits = 2; // mantissa bits with their own contexts

struct ResidualModel {
  std::vector<Prob> length;  // [axis][kind][bucket][node 1..63]
  std::vector<Prob> mantissa;  // [axis][L][node 1..3]
  ResidualModel() : length(3 * kKinds * kBuckets * 64), mantissa(3 * 64 * 4) {}

  static std::size_t length_ctx(int axis, int kind, int bucket) {
    return ((static_cast<std::size_t>(axis) * kKinds + kind) * kBuckets + bucket) * 64;
  }

  void encode(RangeEncoder& rc, std::uint64_t u, int axis, int kind, int bucket) {
    const int len = std::bit_width(u);
    Prob* tree = &length[length_ctx(axis, kind, bucket)];
    for (int i = 5, node = 1; i >= 0; --i) {
      const int b = (len >> i) & 1;
      rc.bit(tree[node], b);
      node = 2 * node + b;
    }
    if (len <= 1) return;
    Prob* m = &mantissa[(static_cast<std::size_t>(axis) * 64 + len) * 4];
    const int rest = len - 1;
    const int modelled = std::min(rest, kModelledBits);
    for (int i = 0, node = 1; i < modelled; ++i) {
      const int b = static_cast<int>((u >> (rest - 1 - i)) & 1);
      rc.bit(m[node], b);
      node = 2 * node + b;
    }
    rc.direct(u, rest - modelled);
  }

  // Returns the length through `len` so the caller can keep it as context.
  std::uint64_t decode(RangeDecoder& rc, int axis, int kind, int bucket, int max_len, int& len) {
    Prob* tree = &length[length_ctx(axis, kind, bucket)];
    int node = 1;
    for (int i = 0; i < 6; ++i) node = 2 * node + rc.bit(tree[node]);
    len = node - 64;
    if (len > max_len) fail("residual longer than the mode allows");
    if (len <= 1) return static_cast<std::uint64_t>(len);
    Prob* m = &mantissa[(static_cast<std::size_t>(axis) * 64 + len) * 4];
    const int rest = len - 1;
    const int modelled = std::min(rest, kModelledBits);
    std::uint64_t u = 1;
    for (int i = 0, n = 1; i < modelled; ++i) {
      const int b = rc.bit(m[n]);
      n = 2 * n + b;
      u = (u << 1) | static_cast<std::uint64_t>(b);
    }
    const int raw = rest - modelled;
    return (u << raw) | rc.direct(raw);
  }
};

std::uint64_t zigzag(std::int64_t r) {
  return (static_cast<std::uint64_t>(r) << 1) ^ static_cast<std::uint64_t>(r >> 63);
}
std::int64_t unzigzag(std::uint64_t u) {
  return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
}

// ---------------------------------------------------------------------------------------------
// Prediction. The kind only depends on the stencil, so both sides agree without signalling it.

enum Kind : std::uint8_t { kNone = 0, kWest = 1, kLinear = 2, kParallelogram = 3, kSouth = 4 };

struct Predictor {
  Kind kind = kNone;
  std::uint32_t a = kInvalid, b = kInvalid, c = kInvalid;  // operands, see predictor_for
};

Predictor predictor_for(std::span<const GridLayout::Stencil> stencil, std::uint32_t i) {
  const GridLayout::Stencil& s = stencil[i];
  if (s.w != kInvalid && s.s != kInvalid && s.sw != kInvalid) return {kParallelogram, s.w, s.s, s.sw};
  if (s.w != kInvalid && s.ww != kInvalid) return {kLinear, s.w, s.ww, kInvalid};
  if (s.w != kInvalid) return {kWest, s.w, kInvalid, kInvalid};
  if (s.s != kInvalid) return {kSouth, s.s, kInvalid, kInvalid};
  return {kNone, i == 0 ? kInvalid : i - 1, kInvalid, kInvalid};
}

// The magnitude class coding vertex i: the mean residual length of its w and s neighbours.
int bucket_for(const std::vector<std::uint8_t>& lengths, const GridLayout::Stencil& s, std::uint32_t i) {
  int v;
  if (s.w != kInvalid && s.s != kInvalid) {
    v = (lengths[s.w] + lengths[s.s] + 1) >> 1;
  } else if (s.w != kInvalid) {
    v = lengths[s.w];
  } else if (s.s != kInvalid) {
    v = lengths[s.s];
  } else {
    v = i == 0 ? 0 : lengths[i - 1];
  }
  return std::min(v, kBuckets - 1);
}

std::int64_t predict_int(const std::int64_t* v, const Predictor& p) {
  switch (p.kind) {
    case kParallelogram: return v[p.a] + v[p.b] - v[p.c];
    case kLinear: return 2 * v[p.a] - v[p.b];
    case kWest:
    case kSouth: return v[p.a];
    case kNone: return p.a == kInvalid ? 0 : v[p.a];
  }
  return 0;
}

// Order-preserving image of float bits: negative floats reversed below the positive ones.
std::uint32_t float_image(float f) {
  const std::uint32_t u = std::bit_cast<std::uint32_t>(f);
  return u ^ ((u >> 31) ? 0xFFFFFFFFu : 0x80000000u);
}
float image_float(std::uint32_t m) {
  return std::bit_cast<float>(m ^ ((m >> 31) ? 0x80000000u : 0xFFFFFFFFu));
}

// Float-mode prediction: computed in binary64, rounded once to binary32; if that is not finite (an
// operand is NaN/inf or the sum overflows) the first operand's own bits predict.
std::uint32_t predict_float(const float* f, const Predictor& p) {
  double d;
  switch (p.kind) {
    case kParallelogram: d = (double{f[p.a]} + double{f[p.b]}) - double{f[p.c]}; break;
    case kLinear: d = (double{f[p.a]} + double{f[p.a]}) - double{f[p.b]}; break;
    case kWest:
    case kSouth: return float_image(f[p.a]);
    case kNone: return p.a == kInvalid ? float_image(0.0f) : float_image(f[p.a]);
    default: d = 0;
  }
  const float r = static_cast<float>(d);
  return std::isfinite(r) ? float_image(r) : float_image(f[p.a]);
}

// ---------------------------------------------------------------------------------------------
// Decimal grids: float = the binary32 nearest to n / 10^k (ties to even), exactly what
// std::from_chars gives for the decimal text.

constexpr int kMaxDecimals = 9;
constexpr std::int64_t kDecimalLimit = std::int64_t{1} << 40;  // |n| < 2^40
constexpr std::array<double, kMaxDecimals + 1> kPow10 = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};

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

// n / 10^k in binary64 is correctly rounded (both exact); rounding that to binary32 is then correct
// unless it landed exactly on a midpoint between two floats, which the slow path settles.
float decimal_float(std::int64_t n, int k) {
  const double d = static_cast<double>(n) / kPow10[k];
  const float f = static_cast<float>(d);
  if (static_cast<double>(f) != d) {
    const float g = std::nextafter(f, d > f ? std::numeric_limits<float>::infinity()
                                            : -std::numeric_limits<float>::infinity());
    if ((static_cast<double>(f) + static_cast<double>(g)) * 0.5 == d) return decimal_float_slow(n, k);
  }
  return f;
}

// The decimal integer for x at k decimals, or false if x is not exactly such a value.
bool decimal_of(float x, int k, std::int64_t& n) {
  if (!std::isfinite(x)) return false;
  const double scaled = static_cast<double>(x) * kPow10[k];
  if (!(std::fabs(scaled) < static_cast<double>(kDecimalLimit) - 1)) return false;
  n = std::llround(scaled);
  if (n == 0 && std::signbit(x)) return false;  // -0 has no decimal integer
  return std::bit_cast<std::uint32_t>(decimal_float(n, k)) == std::bit_cast<std::uint32_t>(x);
}

// ---------------------------------------------------------------------------------------------
// Section layout

enum AxisMode : std::uint8_t { kFloatBits = 0 };  // 1 + k: decimal grid with k decimals

constexpr int kFloatMaxLength = 33;    // zigzag of an image difference in (-2^32, 2^32)
constexpr int kDecimalMaxLength = 42;  // zigzag of n - clamp(prediction), both |.| < 2^40

struct Exception {
  std::uint32_t vertex;
  float value;
};

struct AxisPlan {
  std::uint8_t mode = kFloatBits;
  std::vector<Exception> exceptions;
};

void check_stencil(std::span<const GridLayout::Stencil> stencil, std::size_t n) {
  if (stencil.size() != n) throw Error(ErrorCode::kInternal, "geometry: stencil count != vertex count");
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto& s = stencil[i];
    for (std::uint32_t j : {s.w, s.ww, s.s, s.sw}) {
      if (j != kInvalid && j >= i) throw Error(ErrorCode::kInternal, "geometry: stencil refers forward");
    }
  }
}

// Exceptions it would take to store axis `axis` at k decimals, stopping past `limit`.
std::size_t decimal_misses(std::span<const float> pos, int axis, int k, std::size_t limit) {
  std::size_t misses = 0;
  std::int64_t n;
  for (std::size_t i = axis; i < pos.size(); i += 3) {
    if (!decimal_of(pos[i], k, n) && ++misses > limit) break;
  }
  return misses;
}

// Cheapest decimal grid for the axis, or float bits. Estimates bits: a decimal step of 10^-k costs
// about log2(ulp(x) * 10^k) bits more per coordinate than the float's own ulp; a miss ~40 bits.
AxisPlan plan_axis(std::span<const float> pos, int axis) {
  const std::size_t count = pos.size() / 3;
  double log_ulp_sum = 0;  // sum of log2(ulp(x)) over finite x
  for (std::size_t i = axis; i < pos.size(); i += 3) {
    const float x = std::fabs(pos[i]);
    if (!std::isfinite(x)) continue;
    const int e = x < std::numeric_limits<float>::min() ? -126 : std::ilogb(x);
    log_ulp_sum += e - 23;
  }
  double best_cost = 0;  // float bits, relative
  int best_k = -1;
  for (int k = 0; k <= kMaxDecimals; ++k) {
    const double grid = count * k * std::log2(10.0) + log_ulp_sum;  // bits vs float mode
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
  std::int64_t n;
  for (std::uint32_t i = 0; i < count; ++i) {
    const float x = pos[3 * i + axis];
    if (!decimal_of(x, best_k, n)) plan.exceptions.push_back({i, x});
  }
  return plan;
}

// Integer stand-in for a finite exception coordinate, so its neighbours still predict well.
// (Non-finite ones take their own prediction: residual zero.)
std::int64_t exception_integer(float x, int k) {
  const double scaled = static_cast<double>(x) * kPow10[k];
  const double lim = static_cast<double>(kDecimalLimit - 1);
  return std::llround(std::clamp(scaled, -lim, lim));
}

std::int64_t clamp_decimal(std::int64_t p) { return std::clamp(p, -(kDecimalLimit - 1), kDecimalLimit - 1); }

// Quantization grid. step has at most 23 significant bits so q * step (q < 2^30) is exact in binary64.
struct Grid {
  std::array<float, 3> origin{};
  double step = 0;
  float value(int axis, std::int64_t q) const {
    return static_cast<float>(static_cast<double>(origin[axis]) + static_cast<double>(q) * step);
  }
};

constexpr std::uint64_t kStepLowMask = (std::uint64_t{1} << 30) - 1;  // fraction bits that must be zero

Grid make_grid(std::span<const float> pos, std::uint32_t bits) {
  Grid g;
  double extent = 0;
  for (int a = 0; a < 3; ++a) {
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

// ---------------------------------------------------------------------------------------------

constexpr std::uint8_t kFormatTag = 1;  // first byte: geometry coding revision

std::string encode_with(std::span<const float> pos, std::span<const GridLayout::Stencil> stencil,
                        std::uint32_t bits, const std::array<AxisPlan, 3>& plans, const Grid& grid) {
  const std::uint32_t count = static_cast<std::uint32_t>(pos.size() / 3);
  std::string out;
  put_u8(out, kFormatTag);
  put_varint(out, count);
  put_u8(out, static_cast<std::uint8_t>(bits));
  if (bits) {
    for (float o : grid.origin) put_le(out, std::bit_cast<std::uint32_t>(o), 4);
    put_le(out, std::bit_cast<std::uint64_t>(grid.step), 8);
  } else {
    for (const AxisPlan& plan : plans) {
      put_u8(out, plan.mode);
      if (plan.mode == kFloatBits) continue;
      put_varint(out, plan.exceptions.size());
      std::uint32_t prev = 0;
      for (std::size_t e = 0; e < plan.exceptions.size(); ++e) {
        const Exception& x = plan.exceptions[e];
        put_varint(out, e == 0 ? x.vertex : x.vertex - prev - 1);
        put_le(out, std::bit_cast<std::uint32_t>(x.value), 4);
        prev = x.vertex;
      }
    }
  }

  // Integer values per axis (decimal n, quantized q); float mode reads the floats themselves.
  std::array<std::vector<std::int64_t>, 3> ints;
  std::array<std::vector<float>, 3> floats;
  for (int a = 0; a < 3; ++a) {
    const int mode = plans[a].mode;
    if (!bits && mode == kFloatBits) {
      floats[a].resize(count);
      for (std::uint32_t i = 0; i < count; ++i) floats[a][i] = pos[3 * i + a];
      continue;
    }
    ints[a].resize(count);
    std::size_t e = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      const float x = pos[3 * i + a];
      std::int64_t v = 0;
      if (bits) {
        const double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
        v = grid.step > 0 ? static_cast<std::int64_t>(std::clamp(
                                std::nearbyint((static_cast<double>(x) - grid.origin[a]) / grid.step), 0.0, top))
                          : 0;
        while (v > 0 && !std::isfinite(grid.value(a, v))) --v;  // stay inside float range
      } else if (e < plans[a].exceptions.size() && plans[a].exceptions[e].vertex == i) {
        v = std::isfinite(x) ? exception_integer(x, mode - 1) : 0;  // set when predicted
        ++e;
      } else {
        decimal_of(x, mode - 1, v);
      }
      ints[a][i] = v;
    }
  }

  RangeEncoder rc;
  auto model = std::make_unique<ResidualModel>();
  std::array<std::vector<std::uint8_t>, 3> lengths;
  for (auto& l : lengths) l.assign(count, 0);
  const std::uint64_t qmask = bits ? (std::uint64_t{1} << bits) - 1 : 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Predictor p = predictor_for(stencil, i);
    for (int a = 0; a < 3; ++a) {
      std::uint64_t u;
      if (bits) {
        const std::int64_t pred = std::clamp<std::int64_t>(predict_int(ints[a].data(), p), 0, qmask);
        // Residual modulo 2^bits, taken in [-2^(bits-1), 2^(bits-1)).
        std::uint64_t r = static_cast<std::uint64_t>(ints[a][i] - pred) & qmask;
        std::int64_t sr = static_cast<std::int64_t>(r);
        if (r >> (bits - 1)) sr -= static_cast<std::int64_t>(qmask) + 1;
        u = zigzag(sr);
      } else if (plans[a].mode == kFloatBits) {
        const std::int64_t pred = predict_float(floats[a].data(), p);
        u = zigzag(static_cast<std::int64_t>(float_image(floats[a][i])) - pred);
      } else {
        const std::int64_t pred = clamp_decimal(predict_int(ints[a].data(), p));
        if (!std::isfinite(pos[3 * static_cast<std::size_t>(i) + a])) ints[a][i] = pred;
        u = zigzag(ints[a][i] - pred);
      }
      model->encode(rc, u, a, p.kind, bucket_for(lengths[a], stencil[i], i));
      lengths[a][i] = static_cast<std::uint8_t>(std::bit_width(u));
    }
  }
  const std::string payload = rc.finish();
  put_varint(out, payload.size());
  out += payload;
  return out;
}

}  // namespace

std::string encode_geometry(std::span<const float> positions, std::span<const GridLayout::Stencil> stencil,
                            const GeometryOptions& options) {
  if (positions.size() % 3 != 0) throw Error(ErrorCode::kInternal, "geometry: positions not a multiple of 3");
  if (positions.size() / 3 > std::numeric_limits<std::uint32_t>::max() - 1) {
    throw Error(ErrorCode::kLimit, "geometry: too many vertices");
  }
  if (options.quantize_bits > 30) throw Error(ErrorCode::kInternal, "geometry: quantize_bits must be 0..30");
  check_stencil(stencil, positions.size() / 3);
  std::array<AxisPlan, 3> plans;
  if (options.quantize_bits) {
    return encode_with(positions, stencil, options.quantize_bits, plans,
                       make_grid(positions, options.quantize_bits));
  }
  for (int a = 0; a < 3; ++a) plans[a] = plan_axis(positions, a);
  std::string best = encode_with(positions, stencil, 0, plans, {});
  // The decimal estimate is a heuristic: never do worse than plain float bits.
  if (std::any_of(plans.begin(), plans.end(), [](const AxisPlan& p) { return p.mode != kFloatBits; })) {
    std::string plain = encode_with(positions, stencil, 0, {}, {});
    if (plain.size() < best.size()) best = std::move(plain);
  }
  return best;
}

std::vector<float> decode_geometry(std::string_view bytes, std::span<const GridLayout::Stencil> stencil,
                                   std::uint32_t vertex_count) {
  check_stencil(stencil, vertex_count);
  Reader in(bytes);
  if (in.u8("truncated header") != kFormatTag) fail("unknown geometry coding revision");
  if (in.varint("truncated vertex count") != vertex_count) fail("vertex count mismatch");
  const std::uint32_t bits = in.u8("truncated header");
  if (bits > 30) fail("quantization bits out of range");
  const std::uint32_t count = vertex_count;

  Grid grid;
  std::array<AxisPlan, 3> plans;
  if (bits) {
    for (float& o : grid.origin) {
      o = std::bit_cast<float>(static_cast<std::uint32_t>(in.le(4, "truncated grid origin")));
      if (!std::isfinite(o)) fail("grid origin not finite");
    }
    grid.step = std::bit_cast<double>(in.le(8, "truncated grid step"));
    if (!(grid.step >= 0) || !std::isfinite(grid.step) || std::signbit(grid.step) ||
        (std::bit_cast<std::uint64_t>(grid.step) & kStepLowMask)) {
      fail("invalid grid step");
    }
  } else {
    for (AxisPlan& plan : plans) {
      plan.mode = in.u8("truncated axis mode");
      if (plan.mode > 1 + kMaxDecimals) fail("unknown axis mode");
      if (plan.mode == kFloatBits) continue;
      const std::uint64_t n = in.varint("truncated exception count");
      if (n > count || n > in.left() / 5) fail("exception count exceeds data");
      plan.exceptions.resize(n);
      std::uint64_t prev = 0;
      for (std::uint64_t e = 0; e < n; ++e) {
        const std::uint64_t gap = in.varint("truncated exception");
        const std::uint64_t v = e == 0 ? gap : prev + 1 + gap;
        if (gap >= count || v >= count) fail("exception vertex out of range");
        plan.exceptions[e].vertex = static_cast<std::uint32_t>(v);
        plan.exceptions[e].value = std::bit_cast<float>(static_cast<std::uint32_t>(in.le(4, "truncated exception")));
        prev = v;
      }
    }
  }
  const std::uint64_t payload_size = in.varint("truncated payload size");
  if (payload_size != in.left()) fail("payload size does not match the section");
  RangeDecoder rc(in.take(payload_size, "truncated payload"));

  std::vector<float> out(static_cast<std::size_t>(count) * 3);
  std::array<std::vector<std::int64_t>, 3> ints;
  std::array<std::vector<float>, 3> floats;
  std::array<std::vector<std::uint8_t>, 3> lengths;
  std::array<std::size_t, 3> next_exception{};
  for (int a = 0; a < 3; ++a) {
    if (!bits && plans[a].mode == kFloatBits) {
      floats[a].resize(count);
    } else {
      ints[a].resize(count);
    }
    lengths[a].assign(count, 0);
  }
  auto model = std::make_unique<ResidualModel>();
  const std::uint64_t qmask = bits ? (std::uint64_t{1} << bits) - 1 : 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Predictor p = predictor_for(stencil, i);
    for (int a = 0; a < 3; ++a) {
      const int max_len = bits ? static_cast<int>(bits)
                               : (plans[a].mode == kFloatBits ? kFloatMaxLength : kDecimalMaxLength);
      int len = 0;
      const std::uint64_t u = model->decode(rc, a, p.kind, bucket_for(lengths[a], stencil[i], i), max_len, len);
      lengths[a][i] = static_cast<std::uint8_t>(len);
      const std::int64_t r = unzigzag(u);
      float x;
      if (bits) {
        const std::int64_t pred = std::clamp<std::int64_t>(predict_int(ints[a].data(), p), 0, qmask);
        const std::int64_t q = static_cast<std::int64_t>(static_cast<std::uint64_t>(pred + r) & qmask);
        ints[a][i] = q;
        x = grid.value(a, q);
      } else if (plans[a].mode == kFloatBits) {
        const std::int64_t m = static_cast<std::int64_t>(predict_float(floats[a].data(), p)) + r;
        if (m < 0 || m > 0xFFFFFFFFll) fail("float residual out of range");
        x = image_float(static_cast<std::uint32_t>(m));
        floats[a][i] = x;
      } else {
        const std::int64_t n = clamp_decimal(predict_int(ints[a].data(), p)) + r;
        if (n <= -kDecimalLimit || n >= kDecimalLimit) fail("decimal integer out of range");
        ints[a][i] = n;
        std::size_t& e = next_exception[a];
        if (e < plans[a].exceptions.size() && plans[a].exceptions[e].vertex == i) {
          x = plans[a].exceptions[e++].value;
        } else {
          x = decimal_float(n, plans[a].mode - 1);
        }
      }
      out[3 * static_cast<std::size_t>(i) + a] = x;
    }
    if (rc.overrun()) fail("truncated payload");
  }
  rc.finish();
  return out;
}

float decimal_grid_value(std::int64_t n, int k) {
  if (k < 0 || k > kMaxDecimals || n <= -kDecimalLimit || n >= kDecimalLimit) {
    throw Error(ErrorCode::kInternal, "geometry: decimal grid value out of range");
  }
  return decimal_float(n, k);
}

double max_geometry_error(std::span<const float> original, std::span<const float> decoded) {
  if (original.size() != decoded.size()) throw Error(ErrorCode::kInternal, "geometry: size mismatch");
  double worst = 0;
  for (std::size_t i = 0; i < original.size(); ++i) {
    if (std::bit_cast<std::uint32_t>(original[i]) == std::bit_cast<std::uint32_t>(decoded[i])) continue;
    const double d = std::fabs(static_cast<double>(original[i]) - static_cast<double>(decoded[i]));
    if (std::isnan(d)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, d);
  }
  return worst;
}

}  // namespace qsp
