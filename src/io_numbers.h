// src/io_numbers.h (internal): numbers from text kept exactly (qsp::Numbers), and written back as the
// shortest text that denotes the same value. Shared by the OBJ, OFF and PLY readers and writers.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "qsp/polymesh.h"

namespace qsp::detail {

// A plain decimal token split into its parts: value = (-1)^negative * mantissa * 10^exponent.
struct DecimalParts {
  std::uint64_t mantissa = 0;  // the digits from the first nonzero one (the first 19 when there are more)
  std::int32_t exponent = 0;   // of the mantissa's last digit
  std::uint32_t digits = 0;    // in the mantissa (0 for zero); normalized: the significant digits
  bool negative = false;
};

// Scans [-]digits[.digits][(e|E)[+|-]digits] from `s` (at least one digit). Returns the end of what
// it read, or nullptr when the text does not start that way (inf, nan, "."): the caller's fallback.
// Trailing zeros may stay in the mantissa (up to 19 digits); more than 19 digits come normalized.
const char* scan_decimal(const char* s, const char* end, DecimalParts& out);

// Takes the trailing zeros out of the mantissa: digits becomes the significant digit count.
void normalize(DecimalParts& p);

// The correctly rounded float64 of `p` when one exact operation gives it (Clinger's fast path: an
// integer below 2^53 and a power of ten up to 10^22); false otherwise.
inline bool fast_double(const DecimalParts& p, double& out) {
  static constexpr double kPow10d[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                         1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                         1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  if (p.digits > 19 || p.mantissa > (std::uint64_t{1} << 53) || p.exponent < -22 || p.exponent > 22)
    return false;
  double d = static_cast<double>(p.mantissa);
  d = p.exponent < 0 ? d / kPow10d[-p.exponent] : d * kPow10d[p.exponent];
  out = p.negative ? -d : d;
  return true;
}

// 10^k for k in 0..10, exact in float32.
inline constexpr float kPow10f[11] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f, 1e7f, 1e8f, 1e9f, 1e10f};

// The correctly rounded float32 of `p` when the fast paths give it; false otherwise. An integer below
// 2^24 and a power of ten float32 holds take one float32 step; else the float64 of the value rounds to
// the right float32 unless it lies exactly halfway between two (double rounding: then false).
inline bool fast_float(const DecimalParts& p, float& out) {
  if (p.digits <= 19 && p.mantissa <= (1u << 24) && p.exponent >= -10 && p.exponent <= 10) {
    float f = static_cast<float>(p.mantissa);                                 // exact below 2^24
    f = p.exponent < 0 ? f / kPow10f[-p.exponent] : f * kPow10f[p.exponent];  // one correctly rounded step
    out = p.negative ? -f : f;
    return true;
  }
  double d = 0;
  if (!fast_double(p, d)) return false;
  const double a = d < 0 ? -d : d;
  // float32's normal range, and not halfway: the low 29 of the 52 fraction bits are not 1000...0.
  if (!(a >= 1.1754943508222875e-38 && a < 3.4028234663852886e38)) return false;
  if ((std::bit_cast<std::uint64_t>(d) & 0x1FFFFFFFu) == 0x10000000u) return false;
  out = static_cast<float>(d);
  return true;
}

// A number token read from text: its float32 (as std::from_chars rounds it) and its parts.
struct TextNumber {
  const char* begin = nullptr;  // the token, without a leading '+'
  const char* end = nullptr;
  DecimalParts parts;
  float f = 0.0f;
};

enum class NumberStatus : std::uint8_t {
  kOk,
  kMalformed,   // not a number, or not one token
  kFloatRange,  // float32 cannot hold it (exact reading then tries float64)
  kNotFinite,   // nan, inf
};

// from_chars on the token, for what the fast path does not take.
NumberStatus read_number_slow(const char* s, const char* end, TextNumber& out);

// Reads the number token at `s` (a leading '+' already skipped) whose end `ends(ptr)` accepts: its
// float32 exactly as std::from_chars rounds it, and its parts for exact reading. Accepts what
// std::from_chars<float> accepts; on success out.end is the token's end.
template <class Ends>
inline NumberStatus read_number(const char* s, const char* end, Ends ends, TextNumber& out) {
  out.begin = s;
  const char* p = scan_decimal(s, end, out.parts);
  if (p == nullptr) {  // inf, nan, or no digit: std::from_chars decides
    const NumberStatus st = read_number_slow(s, end, out);
    // Every finite value has digits, which scan_decimal takes: only inf and nan are left.
    if (st == NumberStatus::kMalformed || st == NumberStatus::kOk || !ends(out.end))
      return NumberStatus::kMalformed;
    return st;
  }
  out.end = p;
  if (!ends(p)) return NumberStatus::kMalformed;
  if (fast_float(out.parts, out.f)) return NumberStatus::kOk;
  return read_number_slow(s, p, out);
}

// 10^k for k in 0..19, as integers.
inline constexpr std::uint64_t kPow10u[20] = {1ull,
                                              10ull,
                                              100ull,
                                              1000ull,
                                              10000ull,
                                              100000ull,
                                              1000000ull,
                                              10000000ull,
                                              100000000ull,
                                              1000000000ull,
                                              10000000000ull,
                                              100000000000ull,
                                              1000000000000ull,
                                              10000000000000ull,
                                              100000000000000ull,
                                              1000000000000000ull,
                                              10000000000000000ull,
                                              100000000000000000ull,
                                              1000000000000000000ull,
                                              10000000000000000000ull};

// Decimal digits of m > 0.
inline std::uint32_t digit_count(std::uint64_t m) {
  const int bits = 64 - std::countl_zero(m);
  std::uint32_t d = static_cast<std::uint32_t>((bits * 1233) >> 12);
  return d + (m >= kPow10u[d]);
}

// Reads the commonest token, [-]digits[.digits] of at most 8 significant digits (up to 2^24) and 10
// after the point, whose end `ends(ptr)` accepts, as read_number reads it (kOk, fast_float's first
// step) in a third of its instructions: one loop per digit run, no exponent, no call. False for
// anything else, `out` then undefined: the caller asks read_number.
template <class Ends>
[[gnu::always_inline]] inline bool read_plain_number(const char* s, const char* end, Ends ends,
                                                     TextNumber& out) {
  const char* p = s;
  const bool negative = p < end && *p == '-';
  p += negative;
  const char* const whole = p;
  std::uint64_t m = 0;
  for (std::uint64_t d; p < end && (d = static_cast<unsigned char>(*p) - std::uint64_t{'0'}) <= 9; ++p)
    m = m * 10 + d;
  std::ptrdiff_t digits = p - whole, fraction = 0;
  if (p < end && *p == '.') {
    const char* const first = ++p;
    for (std::uint64_t d; p < end && (d = static_cast<unsigned char>(*p) - std::uint64_t{'0'}) <= 9; ++p)
      m = m * 10 + d;
    fraction = p - first;
    digits += fraction;
  }
  // Up to 19 digits m has not wrapped; below 2^24 it has at most 8 significant ones.
  if (digits == 0 || digits > 19 || fraction > 10 || m > (1u << 24) || !ends(p)) return false;
  float f = static_cast<float>(m);           // exact below 2^24
  if (fraction > 0) f /= kPow10f[fraction];  // fast_float's step, exponent -fraction
  out.begin = s;
  out.end = p;
  out.parts.mantissa = m;
  out.parts.exponent = static_cast<std::int32_t>(-fraction);
  out.parts.digits = m == 0 ? 0 : digit_count(m);
  out.parts.negative = negative;
  out.f = negative ? -f : f;
  return true;
}

// The end of the token at s when it is [-]digits[.digits] of 1 to 19 digits and `ends` accepts it, else
// null: then read_number reads it kOk (0, or between 10^-19 and 10^19: float32's range), which a reader
// that only validates numbers need not ask.
template <class Ends>
[[gnu::always_inline]] inline const char* plain_number_end(const char* s, const char* end, Ends ends) {
  const auto digit = [](char c) { return static_cast<unsigned char>(c) - unsigned{'0'} <= 9; };
  const char* p = s;
  p += p < end && *p == '-';
  const char* const whole = p;
  while (p < end && digit(*p)) ++p;
  std::ptrdiff_t digits = p - whole;
  if (p < end && *p == '.') {
    const char* const first = ++p;
    while (p < end && digit(*p)) ++p;
    digits += p - first;
  }
  return digits > 0 && digits <= 19 && ends(p) ? p : nullptr;
}

// The nearest float64 of `t`'s text (t must be kOk or kFloatRange). False beyond float64's range.
bool text_double(const TextNumber& t, double& out);

// Appends `t` exactly to `n`, raising n's precision when the value needs it. t must have been read
// kOk, or kFloatRange with a finite text_double. Throws nothing.
void push_text_slow(Numbers& n, const TextNumber& t);
// push_text_slow for a caller that appends n.f32 itself (io_text's Tail): `index` values are in
// n.f32 so far; returns the float32 to append as value `index`.
float push_text_at(Numbers& n, std::size_t index, const TextNumber& t);
// Whether float32 holds `t` by its digit count alone: zero, or up to 6 significant digits (FLT_DIG)
// in float32's normal range below 2^24. From 2^24 on, float32's shortest text may be its exact
// integer ("987654016" for 987654000: std::to_chars prefers it to the longer "9.87654e+08").
[[gnu::always_inline]] inline bool float32_by_digits(const TextNumber& t) {
  return t.parts.digits == 0 || (t.parts.digits <= 6 && std::isnormal(t.f) && std::fabs(t.f) < 16777216.0f);
}

// Whether float32 holds `t`'s value exactly: its float32's shortest text denotes the same decimal, or
// (16 or 17 digits, a float64's print) the same float64 (see push_text_at).
bool float32_holds(const TextNumber& t);

[[gnu::always_inline]] inline void push_text(Numbers& n, const TextNumber& t) {
  if (n.precision == Precision::kFloat32 && float32_by_digits(t)) {
    n.f32.push_back(t.f);
    return;
  }
  push_text_slow(n, t);
}

// Binary values, bit for bit.
void push_float32(Numbers& n, float f);
void push_float64(Numbers& n, double d);
void push_integer(Numbers& n, std::int64_t v);
// Appends `count` copies of an exact small value (padding: vt's default v and w are 0).
void push_small(Numbers& n, float f, std::size_t count);

// Appends value i of `n` as the shortest text that denotes it exactly.
void append_number(std::string& out, const Numbers& n, std::size_t i);
// The shortest text of a float32 / float64 (std::to_chars).
void append_float(std::string& out, float f);
void append_double(std::string& out, double d);
// Value i's DecimalNumber, or null when a float holds the value.
const DecimalNumber* find_decimal(const Numbers& n, std::size_t i);

// The float64 nearest the decimal value of f's shortest text.
double shortest_double(float f);
// Value i of `n` as the float64 nearest its decimal value (what a float64 field writes).
double exact_double(const Numbers& n, std::size_t i);

// Inserts one value after every `from` values so each group has `to` (from < to), filled with `fill`.
void widen_groups(Numbers& n, std::size_t from, std::size_t to, float fill);

// Appends `from` to `to` (precision raised as needed, decimals' indices shifted).
void append_numbers(Numbers& to, const Numbers& from);

}  // namespace qsp::detail
