// A small independent PNG reader for tests: every chunk's CRC checked, IDAT inflated with zlib to
// exactly the declared rows, the five filters undone. 8-bit RGB only (what qsp show writes).
#pragma once

#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

namespace qsp::testing {

struct DecodedPng {
  std::string error;  // empty when the file decoded
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  std::vector<std::string> chunks;  // chunk types in file order
};

inline DecodedPng decode_png(const std::string& s) {
  DecodedPng out;
  auto u32 = [&](std::size_t at) {
    return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
  };
  if (s.size() < 8 || s.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return out.error = "no PNG signature", out;
  std::string idat;
  bool ended = false;
  for (std::size_t at = 8; at < s.size();) {
    if (ended) return out.error = "bytes after IEND", out;
    if (at + 12 > s.size()) return out.error = "truncated chunk header", out;
    const std::uint32_t len = u32(at);
    if (at + 12 + std::size_t{len} > s.size()) return out.error = "truncated chunk", out;
    const std::string type = s.substr(at + 4, 4);
    const auto crc = crc32(0L, reinterpret_cast<const Bytef*>(s.data() + at + 4), len + 4);
    if (crc != u32(at + 8 + len)) return out.error = "bad CRC in " + type, out;
    const std::string data = s.substr(at + 8, len);
    out.chunks.push_back(type);
    if (type == "IHDR") {
      if (len != 13) return out.error = "IHDR size", out;
      out.width = u32(at + 8);
      out.height = u32(at + 12);
      if (data[8] != 8 || data[9] != 2 || data[10] != 0 || data[11] != 0 || data[12] != 0)
        return out.error = "not 8-bit RGB, deflate, no interlace", out;
    } else if (type == "IDAT") {
      idat += data;
    } else if (type == "IEND") {
      ended = true;
    }
    at += 12 + std::size_t{len};
  }
  if (!ended) return out.error = "no IEND", out;
  if (out.chunks.empty() || out.chunks[0] != "IHDR") return out.error = "IHDR not first", out;
  const std::size_t stride = 3 * std::size_t{out.width};
  std::string raw((stride + 1) * out.height + 1, '\0');  // one spare byte: longer data is caught
  uLongf raw_size = raw.size();
  if (uncompress(reinterpret_cast<Bytef*>(raw.data()), &raw_size, reinterpret_cast<const Bytef*>(idat.data()),
                 idat.size()) != Z_OK)
    return out.error = "IDAT does not inflate", out;
  if (raw_size != (stride + 1) * out.height) return out.error = "IDAT inflates to the wrong size", out;
  out.rgb.resize(stride * out.height);
  for (std::uint32_t y = 0; y < out.height; ++y) {
    const auto filter = std::uint8_t(raw[y * (stride + 1)]);
    const auto* in = reinterpret_cast<const std::uint8_t*>(raw.data()) + y * (stride + 1) + 1;
    std::uint8_t* row = out.rgb.data() + y * stride;
    const std::uint8_t* up = y ? row - stride : nullptr;
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= 3 ? row[i - 3] : 0, b = up ? up[i] : 0, c = (up && i >= 3) ? up[i - 3] : 0;
      int pred = 0;
      if (filter == 1) pred = a;
      if (filter == 2) pred = b;
      if (filter == 3) pred = (a + b) / 2;
      if (filter == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
        pred = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      if (filter > 4) return out.error = "unknown filter", out;
      row[i] = static_cast<std::uint8_t>(in[i] + pred);
    }
  }
  return out;
}

}  // namespace qsp::testing
