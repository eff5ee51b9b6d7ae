// Exact numbers from text: one scan splits a token into digits and exponent, Clinger's fast path
// rounds most of them without std::from_chars, and the precision class (qsp/polymesh.h) is decided
// from the digit count, falling back to comparing with float32's shortest text only where the count
// cannot decide (7 to 9 digits; 16 and 17, whose float64's shortest text may be shorter).
#include "io_numbers.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <system_error>

namespace qsp::detail {
namespace {

// The exponent after a mantissa ("e-5"), moving p past it; 0 (p unmoved) when there is none. Saturates
// far beyond any float64.
std::int64_t scan_exponent(const char*& p, const char* end) {
  if (p == end || (*p != 'e' && *p != 'E')) return 0;
  const char* q = p + 1;
  bool negative = false;
  if (q < end && (*q == '+' || *q == '-')) negative = *q++ == '-';
  if (q == end || static_cast<unsigned>(static_cast<unsigned char>(*q) - '0') > 9) return 0;
  std::int64_t e = 0;
  for (; q < end && static_cast<unsigned>(static_cast<unsigned char>(*q) - '0') <= 9; ++q) {
    if (e < 100000000) e = e * 10 + (*q - '0');
  }
  p = q;
  return negative ? -e : e;
}

// Whether the shortest text of `value` denotes the decimal `p` (normalized).
template <class T>
bool shortest_is(T value, const DecimalParts& p) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  DecimalParts q;
  const char* e = scan_decimal(buf, r.ptr, q);
  normalize(q);
  return e == r.ptr && q.digits == p.digits && q.mantissa == p.mantissa &&
         (p.digits == 0 || (q.exponent == p.exponent && q.negative == p.negative));
}

// The significant digits of a token scan_decimal accepted, for a DecimalNumber.
std::string significant_digits(const char* s, const char* end) {
  std::string d;
  for (const char* p = s; p < end; ++p) {
    if (*p == 'e' || *p == 'E') break;
    if (*p >= '0' && *p <= '9' && (*p != '0' || !d.empty())) d += *p;
  }
  while (!d.empty() && d.back() == '0') d.pop_back();
  return d;
}

// Whether `t` (p: its parts, normalized) is the shortest text of d. For more than 17 digits only the
// exact integer can be: std::to_chars prefers "577766900000000128" to "5.777669000000001e+17".
bool shortest_text_of(double d, const TextNumber& t, const DecimalParts& p) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, d);
  DecimalParts q;
  if (scan_decimal(buf, r.ptr, q) != r.ptr) return false;
  normalize(q);
  return q.negative == p.negative && q.exponent == p.exponent &&
         significant_digits(buf, r.ptr) == significant_digits(t.begin, t.end);
}

}  // namespace

double shortest_double(float f) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, f);
  double d = 0;
  std::from_chars(buf, r.ptr, d);
  return d;
}

namespace {

// Gives `n`, whose first `count` float32 values are its values so far, float64 values too.
void promote_to_float64(Numbers& n, std::size_t count) {
  if (n.precision != Precision::kFloat32) return;
  n.f64.resize(count);
  for (std::size_t i = 0; i < count; ++i) n.f64[i] = shortest_double(n.f32[i]);
  n.precision = Precision::kFloat64;
}
void promote_to_float64(Numbers& n) { promote_to_float64(n, n.f32.size()); }

}  // namespace

namespace {

inline bool is_digit(char c) { return static_cast<unsigned>(static_cast<unsigned char>(c) - '0') <= 9; }

// scan_decimal for tokens with more than 19 digits: each digit's position tracked.
[[gnu::noinline]] const char* scan_long(const char* s, const char* end, DecimalParts& out) {
  const char* p = s;
  out = DecimalParts{};
  if (p < end && *p == '-') {
    out.negative = true;
    ++p;
  }
  std::uint64_t m = 0;
  std::int64_t index = 0, first = -1, last = -1;  // digit positions
  int taken = 0;                                  // digits in m, from the first nonzero one
  const auto digits = [&] {
    for (; p < end && is_digit(*p); ++p) {
      const unsigned c = static_cast<unsigned>(*p - '0');
      if (c != 0) {
        if (first < 0) first = index;
        last = index;
      }
      if (first >= 0 && taken < 19) {
        m = m * 10 + c;
        ++taken;
      }
      ++index;
    }
  };
  digits();
  const std::int64_t integer_digits = index;
  if (p < end && *p == '.') {
    ++p;
    digits();
  }
  if (index == 0) return nullptr;
  const std::int64_t e = scan_exponent(p, end);
  if (first < 0) return p;  // zero
  const std::int64_t significant = last - first + 1;
  if (significant <= 19) m /= kPow10u[taken - significant];  // drop the trailing zeros taken
  out.mantissa = m;
  out.digits = static_cast<std::uint32_t>(std::min<std::int64_t>(significant, 0xFFFFFFFF));
  const std::int64_t exponent = (index - 1 - last) - (index - integer_digits) + e;
  out.exponent = static_cast<std::int32_t>(std::clamp<std::int64_t>(exponent, INT32_MIN / 2, INT32_MAX / 2));
  return p;
}

}  // namespace

namespace {

// Four ASCII digits at p (first in the lowest byte): whether they are, and their value.
inline bool four_digits(const char* p, std::uint32_t& value) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  if ((v & 0xF0F0F0F0u) != 0x30303030u || ((v + 0x06060606u) & 0xF0F0F0F0u) != 0x30303030u) return false;
  v -= 0x30303030u;
  v = v * 10 + (v >> 8);  // bytes 0 and 2: the two-digit pairs
  value = (v & 0xFFu) * 100 + ((v >> 16) & 0xFFu);
  return true;
}

// Digits from p into m (four at a time where the text allows); returns the end.
inline const char* read_digits(const char* p, const char* end, std::uint64_t& m) {
  std::uint32_t four = 0;
  while (end - p >= 4 && four_digits(p, four)) {
    m = m * 10000 + four;
    p += 4;
  }
  for (;;) {
    if (p == end) return p;
    const std::uint64_t d = static_cast<unsigned char>(*p) - std::uint64_t{'0'};
    if (d > 9) return p;
    m = m * 10 + d;
    ++p;
  }
}

}  // namespace

// The common token (at most 19 digits) in one tight loop: the digits accumulate into one integer;
// trailing zeros stay in it until normalize() (exact reading only) takes them out.
const char* scan_decimal(const char* s, const char* end, DecimalParts& out) {
  const char* p = s;
  out.negative = p < end && *p == '-';
  p += out.negative;
  const char* digits = p;
  std::uint64_t m = 0;
  p = read_digits(p, end, m);
  std::ptrdiff_t n = p - digits, fraction = 0;
  if (p < end && *p == '.') {
    const char* f = ++p;
    p = read_digits(p, end, m);
    fraction = p - f;
    n += fraction;
  }
  if (n == 0) return nullptr;
  if (n > 19) return scan_long(s, end, out);  // m may have wrapped
  std::int64_t e = -fraction;
  if (p < end && (*p == 'e' || *p == 'E')) e += scan_exponent(p, end);
  out.mantissa = m;
  out.digits = m == 0 ? 0 : digit_count(m);
  out.exponent = static_cast<std::int32_t>(std::clamp<std::int64_t>(e, INT32_MIN / 2, INT32_MAX / 2));
  return p;
}

void normalize(DecimalParts& p) {
  if (p.mantissa == 0 || p.digits > 19) return;
  while (p.mantissa % 10 == 0) {
    p.mantissa /= 10;
    ++p.exponent;
  }
  p.digits = digit_count(p.mantissa);
}

NumberStatus read_number_slow(const char* s, const char* end, TextNumber& out) {
  float f = 0.0f;
  const auto [ptr, ec] = std::from_chars(s, end, f);
  out.end = ptr;
  if (ec == std::errc::invalid_argument) return NumberStatus::kMalformed;
  if (ec == std::errc::result_out_of_range) return NumberStatus::kFloatRange;
  if (!std::isfinite(f)) return NumberStatus::kNotFinite;
  out.f = f;
  return NumberStatus::kOk;
}

bool text_double(const TextNumber& t, double& out) {
  if (fast_double(t.parts, out)) return true;
  const auto [ptr, ec] = std::from_chars(t.begin, t.end, out);
  return ec == std::errc() && std::isfinite(out);
}

namespace {

// Whether the shortest text of f, the float32 nearest the normalized decimal p (7 to 9 digits), is p,
// decided with float64 arithmetic (1 or 0), or -1 where that cannot decide (a tie, a value exactly on
// an interval's end, exponents beyond the fast path, 2^24 and above). Ryu's rule, which std::to_chars
// follows below 2^24: no shorter decimal rounds to f, and no decimal of p's length that rounds to f is
// closer to it.
int shortest_is_fast(float f, const DecimalParts& p) {
  const float af = std::fabs(f);
  // From 2^24 on std::to_chars may print the exact integer instead (see float32_by_digits).
  if (!std::isnormal(af) || af >= 16777216.0f) return -1;
  const double x = af;
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(af);  // normal: its neighbours are bits -+ 1
  const double lo = (x + std::bit_cast<float>(bits - 1)) / 2, hi = (x + std::bit_cast<float>(bits + 1)) / 2;
  const auto value = [](std::uint64_t m, std::int32_t e, double& out) {
    DecimalParts q;
    q.mantissa = m;
    q.exponent = e;
    return fast_double(q, out);
  };
  const auto inside = [&](std::uint64_t m, std::int32_t e) {  // 1 rounds to f, 0 not, -1 unknown
    double v = 0;
    if (!value(m, e, v) || v == lo || v == hi) return -1;
    return lo < v && v < hi ? 1 : 0;
  };
  const std::uint64_t shorter = p.mantissa / 10;
  for (const std::uint64_t c : {shorter, shorter + 1}) {
    const int r = inside(c, p.exponent + 1);
    if (r != 0) return r < 0 ? -1 : 0;
  }
  for (const int step : {-1, 1}) {
    const int r = inside(p.mantissa + step, p.exponent);
    if (r < 0) return -1;
    if (r == 0) continue;
    double half = 0;  // halfway between p and its neighbour
    if (!value((2 * p.mantissa + step) * 5, p.exponent - 1, half) || half == x) return -1;
    if (step > 0 ? x > half : x < half) return 0;
  }
  return 1;
}

// A 16- or 17-digit text `p` is the float64 `d` it rounds to ("0.10000000000000001" is 0.1): its
// digits beyond d's shortest text are spelling. Sets `f` to the float32 that shortest text reads as
// (the text's own float32 but where d lies exactly halfway between two float32s, and the text and the
// shortest text round to different ones) and returns whether that text is f's shortest text: then
// float32 holds the value.
bool printed_float64(double d, const DecimalParts& p, float& f) {
  const float g = static_cast<float>(d);
  if (!std::isfinite(g) || g == 0.0f) return false;  // beyond float32's range: f stays the text's
  f = g;
  // Halfway: in float32's normal range the low 29 of d's 52 fraction bits are 1000...0.
  const bool tie =
      std::fabs(d) >= 1.1754943508222875e-38
          ? (std::bit_cast<std::uint64_t>(d) & 0x1FFFFFFFu) == 0x10000000u
          : d != g && (static_cast<double>(g) + std::nextafter(g, d > g ? 1.0f : -1.0f)) / 2 == d;
  if (tie) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, d);
    std::from_chars(buf, r.ptr, f);
  }
  // A float32's shortest text has at most 9 significant digits below 10^9 (above, maybe its exact
  // integer), and lies within one float64 ulp of p: at most 23 units of p's last digit. So p's digits
  // after the ninth are then within 23 of a multiple of 10^(digits - 9): most prints skip the test.
  const std::uint64_t unit = kPow10u[p.digits - 9], tail = p.mantissa % unit;
  if (std::fabs(d) < 1e9 && tail > 23 && unit - tail > 23) return false;
  return shortest_double(f) == d;
}

// Whether `t` (p: its parts, normalized) is its float32's shortest text, or float32_by_digits says so.
bool float32_text(const TextNumber& t, const DecimalParts& p) {
  if (float32_by_digits(t)) return true;
  // Float32's shortest text has up to 9 significant digits, or from 2^24 on its exact integer when
  // that is shorter than the exponent form (up to 14 characters: "194315862016").
  const bool candidate =
      p.digits <= 9 || (p.digits <= 15 && p.exponent >= 0 && std::fabs(t.f) >= 16777216.0f);
  if (!candidate || !std::isfinite(t.f) || t.f == 0.0f) return false;
  const int fast = shortest_is_fast(t.f, p);
  return fast > 0 || (fast < 0 && shortest_is(t.f, p));
}

}  // namespace

bool float32_holds(const TextNumber& t) {
  if (float32_by_digits(t)) return true;
  DecimalParts p = t.parts;
  normalize(p);
  if (float32_text(t, p)) return true;
  double d = 0;
  float f = t.f;
  // A tie may pick the other float32 than the text's own, which the QuadMesh readers keep: not held.
  return (p.digits == 16 || p.digits == 17) && text_double(t, d) && printed_float64(d, p, f) && f == t.f;
}

float push_text_at(Numbers& n, std::size_t index, const TextNumber& t) {
  DecimalParts p = t.parts;
  normalize(p);
  bool float32 = float32_text(t, p);
  if (float32 && n.precision == Precision::kFloat32) return t.f;
  double d = 0;
  const bool in_range = text_double(t, d);
  if (!in_range) d = p.negative ? -std::numeric_limits<double>::max() : std::numeric_limits<double>::max();
  float f = t.f;
  // 16 or 17 digits are the float64 they round to, whose shortest text may be shorter; up to 15 digits
  // are that text already (no two such decimals round to one float64).
  if (!float32 && in_range && (p.digits == 16 || p.digits == 17)) {
    float32 = printed_float64(d, p, f);
    if (float32 && n.precision == Precision::kFloat32) return f;
  }
  promote_to_float64(n, index);
  // Up to 17 significant digits is a float64 printed exactly (printf's %.17g): the float64 is the value.
  // So is more when the text is the float64's shortest text (its exact integer, from 10^17 on).
  const bool float64 =
      float32 || p.digits <= 17 || (in_range && p.exponent >= 0 && shortest_text_of(d, t, p));
  if (!float64) {
    n.precision = Precision::kDecimal;
    DecimalNumber x;
    x.index = static_cast<std::uint32_t>(index);
    x.negative = p.negative;
    x.exponent = p.exponent;
    x.digits = significant_digits(t.begin, t.end);
    n.decimals.push_back(std::move(x));
  }
  n.f64.push_back(d);
  // A value float32 cannot hold (beyond its range) keeps the overflowed or flushed mirror.
  return std::isfinite(f) && f != 0.0f ? f : static_cast<float>(d);
}

void push_text_slow(Numbers& n, const TextNumber& t) {
  const float f = push_text_at(n, n.f32.size(), t);
  n.f32.push_back(f);
}

void push_float32(Numbers& n, float f) {
  n.f32.push_back(f);
  if (n.precision != Precision::kFloat32) n.f64.push_back(shortest_double(f));
}

void push_float64(Numbers& n, double d) {
  promote_to_float64(n);
  n.f32.push_back(static_cast<float>(d));
  n.f64.push_back(d);
}

void push_integer(Numbers& n, std::int64_t v) {
  constexpr std::int64_t kExact = std::int64_t{1} << 24;  // float32 holds every integer up to here
  if (v >= -kExact && v <= kExact) return push_float32(n, static_cast<float>(v));
  push_float64(n, static_cast<double>(v));
}

void push_small(Numbers& n, float f, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) push_float32(n, f);
}

void append_float(std::string& out, float f) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, f);
  out.append(buf, r.ptr);
}

void append_double(std::string& out, double d) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, d);
  out.append(buf, r.ptr);
}

namespace {

// A DecimalNumber as text scan_decimal reads back to the same parts: positional when short.
void append_decimal(std::string& out, const DecimalNumber& x) {
  if (x.negative) out += '-';
  const std::int64_t len = static_cast<std::int64_t>(x.digits.size());
  const std::int64_t e = x.exponent;
  if (e >= 0 && e <= 6) {
    out += x.digits;
    out.append(static_cast<std::size_t>(e), '0');
  } else if (e < 0 && -e < len) {
    out.append(x.digits, 0, static_cast<std::size_t>(len + e));
    out += '.';
    out.append(x.digits, static_cast<std::size_t>(len + e));
  } else if (e < 0 && -e - len <= 6) {
    out += "0.";
    out.append(static_cast<std::size_t>(-e - len), '0');
    out += x.digits;
  } else {
    out += x.digits[0];
    if (len > 1) {
      out += '.';
      out.append(x.digits, 1);
    }
    out += 'e';
    out += std::to_string(e + len - 1);
  }
}

}  // namespace

// The decimal of value i, or null when a float holds it.
const DecimalNumber* find_decimal(const Numbers& n, std::size_t i) {
  if (n.precision != Precision::kDecimal) return nullptr;
  const auto it = std::lower_bound(n.decimals.begin(), n.decimals.end(), i,
                                   [](const DecimalNumber& d, std::size_t at) { return d.index < at; });
  return it != n.decimals.end() && it->index == i ? &*it : nullptr;
}

void append_number(std::string& out, const Numbers& n, std::size_t i) {
  if (n.precision == Precision::kFloat32) return append_float(out, n.f32[i]);
  if (const DecimalNumber* d = find_decimal(n, i)) return append_decimal(out, *d);
  append_double(out, n.f64[i]);
}

double exact_double(const Numbers& n, std::size_t i) {
  return n.precision == Precision::kFloat32 ? shortest_double(n.f32[i]) : n.f64[i];
}

void widen_groups(Numbers& n, std::size_t from, std::size_t to, float fill) {
  Numbers w;
  w.precision = n.precision;
  const std::size_t groups = from == 0 ? 0 : n.size() / from;
  w.f32.reserve(groups * to);
  if (!n.f64.empty()) w.f64.reserve(groups * to);
  std::size_t d = 0;
  for (std::size_t g = 0; g < groups; ++g) {
    for (std::size_t c = 0; c < to; ++c) {
      if (c < from) {
        const std::size_t i = g * from + c;
        if (d < n.decimals.size() && n.decimals[d].index == i) {
          w.decimals.push_back(n.decimals[d++]);
          w.decimals.back().index = static_cast<std::uint32_t>(w.f32.size());
        }
        w.f32.push_back(n.f32[i]);
        if (!n.f64.empty()) w.f64.push_back(n.f64[i]);
      } else {
        push_float32(w, fill);
      }
    }
  }
  n = std::move(w);
}

void append_numbers(Numbers& to, const Numbers& from) {
  if (from.precision != Precision::kFloat32) promote_to_float64(to);
  const std::size_t base = to.f32.size();
  to.f32.insert(to.f32.end(), from.f32.begin(), from.f32.end());
  if (to.precision != Precision::kFloat32) {
    if (from.precision == Precision::kFloat32) {
      for (const float f : from.f32) to.f64.push_back(shortest_double(f));
    } else {
      to.f64.insert(to.f64.end(), from.f64.begin(), from.f64.end());
    }
  }
  for (DecimalNumber x : from.decimals) {
    x.index += static_cast<std::uint32_t>(base);
    to.decimals.push_back(std::move(x));
  }
  if (from.precision == Precision::kDecimal) to.precision = Precision::kDecimal;
}

}  // namespace qsp::detail
