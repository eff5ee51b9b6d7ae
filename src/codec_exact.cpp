// The exact positions section (format 3.6; format-spec/qsp_format.md, "Exact positions section"): per
// coordinate the residual between its exact value and the binary32 the geometry holds, in decimal or
// binary64 steps, packed at a fixed width per axis. The exact values section (format 3.13) codes texture
// coordinates, normals and colours the same way, with as many axes as the values have components.
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "geometry_values.h"
#include "qsp/error.h"

namespace qsp {
namespace {

constexpr std::uint8_t kMostDecimals = 22, kBinary64 = 64;
constexpr double kProductBound = 4611686018427387904.0;  // 2^62
using Wide = __int128;
constexpr Wide kIntBound = Wide{1} << 63;

// 10^k for k <= 22: every one is exact in binary64.
constexpr std::array<double, kMostDecimals + 1> kPow10 = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                                          1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                                          1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// A residual's field: the geometry coder's zigzag, for a residual checked to fit 64 bits.
std::uint64_t zigzag(Wide r) {
  if (r >= kIntBound || r < -kIntBound) throw Error(ErrorCode::kInternal, "encode: exact residual past 2^63");
  return zigzag64(static_cast<std::int64_t>(r));
}
unsigned width(std::uint64_t u) { return static_cast<unsigned>(std::bit_width(u)); }

// Binary64 bits as an integer that increases with the value: -0 is -1, +0 is 0.
Wide ord(double x) {
  const auto u = std::bit_cast<std::uint64_t>(x);
  return u >> 63 ? -1 - Wide(u & ~(std::uint64_t{1} << 63)) : Wide(u);
}
double from_ord(Wide o) {
  return std::bit_cast<double>(o >= 0 ? std::uint64_t(o) : std::uint64_t(-1 - o) | (std::uint64_t{1} << 63));
}

bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

// M: f times 10^k rounded to the nearest integer, halves away from zero; false past 2^62.
bool nearest_scaled(float f, unsigned k, std::int64_t& m) {
  const double p = static_cast<double>(f) * kPow10[k];
  if (!(std::fabs(p) < kProductBound)) return false;
  m = static_cast<std::int64_t>(std::round(p));
  return true;
}

// The binary64 nearest the decimal n * 10^-k (what reading the text "Ne-k" gives).
double decimal_value(Wide n, unsigned k, float f) {
  if (n == 0) return std::copysign(0.0, static_cast<double>(f));
  std::string text = n < 0 ? "-" : "";
  text += std::to_string(std::uint64_t(n < 0 ? -n : n));
  text += "e-";
  text += std::to_string(k);
  double v = 0;
  std::from_chars(text.data(), text.data() + text.size(), v);
  return v;
}

// A value's shortest text as digits * 10^exponent; decimals() is how many digits follow the point.
struct Shortest {
  std::uint64_t digits = 0;
  int exponent = 0;  // of the last digit
  int decimals() const { return exponent < 0 ? -exponent : 0; }
};
Shortest shortest(double d) {
  char text[40];
  const char* end = std::to_chars(text, text + sizeof text, d, std::chars_format::scientific).ptr;
  Shortest s;
  const char* p = text + (*text == '-');
  int digits_after_point = 0;
  bool after_point = false;
  for (; p < end && *p != 'e'; ++p) {
    if (*p == '.') {
      after_point = true;
      continue;
    }
    s.digits = 10 * s.digits + static_cast<std::uint64_t>(*p - '0');
    digits_after_point += after_point;
  }
  int e = 0;
  std::from_chars(p + 1 + (p[1] == '+'), end, e);
  s.exponent = e - digits_after_point;
  return s;
}

// The residuals of one axis of `axes` in decimal steps of 10^-k; false if one does not fit.
bool decimal_residuals(std::span<const float> f, std::span<const double> d, std::size_t axes,
                       std::size_t axis, unsigned k, std::vector<std::uint64_t>& out) {
  const std::size_t n = f.size() / axes;
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Shortest s = shortest(d[axes * i + axis]);
    Wide value = s.digits;
    for (int e = s.exponent + static_cast<int>(k); e > 0; --e) {
      value *= 10;
      if (value >= kIntBound) return false;
    }
    if (d[axes * i + axis] < 0) value = -value;
    std::int64_t m = 0;
    if (!nearest_scaled(f[axes * i + axis], k, m)) return false;
    const Wide r = value - m;
    if (r >= kIntBound || r < -kIntBound) return false;  // decimal steps cannot say it: binary64 ones
    out[i] = zigzag(r);
  }
  return true;
}

void put_bits(std::string& out, std::uint64_t& acc, unsigned& used, std::uint64_t value, unsigned bits) {
  for (unsigned b = 0; b < bits; ++b) {
    acc |= ((value >> b) & 1u) << used;
    if (++used == 8) out.push_back(static_cast<char>(acc)), acc = 0, used = 0;
  }
}

}  // namespace

std::string encode_exact_values(std::span<const float> values, std::span<const double> exact,
                                std::size_t axes) {
  if (axes == 0 || values.size() != exact.size() || values.size() % axes != 0)
    throw Error(ErrorCode::kInternal, "encode: exact values do not match their binary32 values");
  for (std::size_t i = 0; i < exact.size(); ++i)
    if (!std::isfinite(exact[i]) || !same_bits(static_cast<float>(exact[i]), values[i]))
      throw Error(ErrorCode::kUsage, "encode: exact value " + std::to_string(i) +
                                         " is not finite or does not round to its binary32 value");
  const std::size_t n = values.size() / axes;
  std::vector<std::uint8_t> mode(axes), bits(axes);
  std::vector<std::vector<std::uint64_t>> fields(axes);
  for (std::size_t a = 0; a < axes; ++a) {
    std::vector<std::uint64_t> binary(n);
    std::uint64_t most = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Wide r = ord(exact[axes * i + a]) - ord(static_cast<double>(values[axes * i + a]));
      most |= binary[i] = zigzag(r);  // |r| < 2^62 between finite values rounding to one binary32
    }
    mode[a] = kBinary64, bits[a] = static_cast<std::uint8_t>(width(most)), fields[a] = std::move(binary);
    int k = 0;
    for (std::size_t i = 0; i < n; ++i) k = std::max(k, shortest(exact[axes * i + a]).decimals());
    std::vector<std::uint64_t> decimal;
    if (k > kMostDecimals || !decimal_residuals(values, exact, axes, a, static_cast<unsigned>(k), decimal))
      continue;
    std::uint64_t most_decimal = 0;
    for (std::uint64_t u : decimal) most_decimal |= u;
    if (width(most_decimal) > bits[a]) continue;
    mode[a] = static_cast<std::uint8_t>(k), bits[a] = static_cast<std::uint8_t>(width(most_decimal));
    fields[a] = std::move(decimal);
  }
  std::string out(mode.begin(), mode.end());
  out.append(bits.begin(), bits.end());
  std::uint64_t acc = 0;
  unsigned used = 0;
  for (std::size_t a = 0; a < axes; ++a)
    for (std::uint64_t u : fields[a]) put_bits(out, acc, used, u, bits[a]);
  if (used) out.push_back(static_cast<char>(acc));
  return out;
}

std::vector<double> decode_exact_values(std::string_view payload, std::uint64_t base_offset,
                                        std::span<const float> values, std::size_t axes,
                                        std::string_view section, std::string_view element) {
  const auto fail = [&](const std::string& what, std::uint64_t at) {
    throw Error(ErrorCode::kFormat, std::string(section) + ": " + what + " (at byte offset " +
                                        std::to_string(base_offset + at) + ")");
  };
  if (axes == 0 || values.size() % axes != 0)
    throw Error(ErrorCode::kInternal, "decode: exact values over a partial array");
  if (payload.size() < 2 * axes) fail("the section ends before its modes and widths", payload.size());
  const auto byte = [&](std::size_t i) { return static_cast<std::uint8_t>(payload[i]); };
  std::uint64_t per_value = 0;
  for (std::size_t a = 0; a < axes; ++a) {
    if (byte(a) > kMostDecimals && byte(a) != kBinary64)
      fail("axis " + std::to_string(a) + " has mode " + std::to_string(byte(a)) + " (0-22 or 64)", a);
    if (byte(axes + a) > 64)
      fail("axis " + std::to_string(a) + " has residuals of " + std::to_string(byte(axes + a)) +
               " bits (0-64)",
           axes + a);
    per_value += byte(axes + a);
  }
  const std::uint64_t n = values.size() / axes, head = 2 * axes;
  const std::uint64_t total = n * per_value;
  const std::uint64_t need = (total + 7) / 8;
  if (payload.size() - head != need)
    fail("the residuals take " + std::to_string(need) + " bytes, the section has " +
             std::to_string(payload.size() - head),
         head);
  if (total % 8 && (byte(head + total / 8) >> (total % 8)) != 0)
    fail("bits after the last residual are not 0", head + total / 8);
  std::vector<double> out(values.size());
  std::uint64_t at = 0;  // bit position after the widths
  const auto read = [&](unsigned bits) {
    std::uint64_t u = 0;
    for (unsigned b = 0; b < bits; ++b, ++at) u |= std::uint64_t((byte(head + at / 8) >> (at % 8)) & 1u) << b;
    return u;
  };
  for (std::size_t a = 0; a < axes; ++a) {
    const unsigned mode = byte(a), bits = byte(axes + a);
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::uint64_t field_at = head + at / 8;
      const Wide r = unzigzag64(read(bits));
      const float f = values[axes * i + a];
      const std::string where = std::string(element) + " " + std::to_string(i) + " axis " + std::to_string(a);
      double v = 0;
      if (mode == kBinary64) {
        const Wide o = ord(static_cast<double>(f)) + r;
        if (o > ord(std::numeric_limits<double>::max()) || o < ord(-std::numeric_limits<double>::max()))
          fail(where + " is not a finite number", field_at);
        v = from_ord(o);
      } else {
        std::int64_t m = 0;
        if (!nearest_scaled(f, mode, m))
          fail(where + ": its binary32 times 10^" + std::to_string(mode) + " is not below 2^62", field_at);
        const Wide value = m + r;
        if (value >= kIntBound || value <= -kIntBound) fail(where + " has a decimal beyond 2^63", field_at);
        v = decimal_value(value, mode, f);
      }
      if (!same_bits(static_cast<float>(v), f))
        fail(where + " has a value whose nearest binary32 is not the binary32 it refines", field_at);
      out[axes * i + a] = v;
    }
  }
  return out;
}

bool exact_needed(std::span<const float> values, std::span<const double> exact) {
  for (std::size_t i = 0; i < exact.size() && i < values.size(); ++i) {
    const double d = exact[i];
    if (d == static_cast<double>(values[i]) && std::signbit(d) == std::signbit(values[i])) continue;
    // The value the binary32's shortest text denotes ("0.1"): what a writer of the binary32 prints.
    char text[32];
    const char* end = std::to_chars(text, text + sizeof text, values[i]).ptr;
    double shown = 0;
    std::from_chars(text, end, shown);
    if (shown != d || std::signbit(shown) != std::signbit(d)) return true;
  }
  return false;
}

std::string encode_exact_values_section(std::span<const ExactArray> arrays) {
  std::uint8_t kinds = 0;
  std::string blocks;
  for (std::size_t k = 0; k < arrays.size() && k < 8; ++k) {
    if (arrays[k].exact.empty()) continue;
    kinds |= static_cast<std::uint8_t>(1u << k);
    const std::string block = encode_exact_values(arrays[k].values, arrays[k].exact, arrays[k].axes);
    put_varint(blocks, block.size());
    blocks += block;
  }
  if (kinds == 0) throw Error(ErrorCode::kInternal, "encode: an exact values section with no values");
  return std::string(1, static_cast<char>(kinds)) + blocks;
}

std::vector<std::vector<double>> decode_exact_values_section(std::string_view payload,
                                                             std::uint64_t base_offset,
                                                             std::span<const ExactArray> arrays) {
  constexpr const char* kSection = "exact values section";
  ByteReader r(payload, base_offset, kSection);
  const std::uint64_t kinds_at = r.offset();
  const std::uint8_t kinds = r.u8("kinds");
  if (kinds == 0 || (kinds >> arrays.size()) != 0)
    r.fail_at("kinds " + std::to_string(kinds) + " (bits 0-" + std::to_string(arrays.size() - 1) +
                  ", at least one)",
              kinds_at);
  std::vector<std::vector<double>> out(arrays.size());
  for (std::size_t k = 0; k < arrays.size(); ++k) {
    if (!(kinds >> k & 1u)) continue;
    const std::uint64_t at = r.offset();
    if (arrays[k].values.empty())
      r.fail_at(std::string(arrays[k].name) + " have exact values, and the mesh has none", at);
    const std::uint64_t length = r.varint("block length");
    if (length > r.left()) r.fail_at("a block runs past the section", at);
    const std::uint64_t block_at = r.offset();
    const std::string_view block = r.take(length, "block");
    out[k] =
        decode_exact_values(block, block_at, arrays[k].values, arrays[k].axes, kSection, arrays[k].element);
  }
  if (r.left() != 0) r.fail_at("bytes after the last block", r.offset());
  return out;
}

std::string encode_exact_section(std::span<const float> positions, std::span<const double> exact) {
  if (positions.size() != exact.size() || positions.size() % 3 != 0)
    throw Error(ErrorCode::kInternal, "encode: exact positions do not match the positions");
  return encode_exact_values(positions, exact, 3);
}

std::vector<double> decode_exact_section(std::string_view payload, std::uint64_t base_offset,
                                         std::span<const float> positions) {
  return decode_exact_values(payload, base_offset, positions, 3, "exact positions section", "vertex");
}

}  // namespace qsp
