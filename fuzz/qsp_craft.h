// Building and re-sealing .qsp containers by hand, for the fuzzers and tests/test_hostile.cpp.
// Mirrors the container layout of src/codec.cpp: magic (8), major, minor, flags, file size (LEB128,
// counting itself), tagged sections (tag, LEB128 length, payload), XXH64 (seed 0, little-endian) of
// every byte before it. Header-only; uses xxhash inline so no link dependency is needed.
#pragma once

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace qsp::craft {

inline constexpr unsigned char kMagic[8] = {0x89, 'Q', 'S', 'P', 0x0D, 0x0A, 0x1A, 0x0A};
inline constexpr std::size_t kFixedHeader = 11;  // magic, major, minor, flags
inline constexpr std::size_t kChecksumBytes = 8;
inline constexpr std::uint8_t kTagCounts = 0x01, kTagTopology = 0x02, kTagGeometry = 0x03, kTagOrder = 0x04;

inline void put_varint(std::string& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>(static_cast<std::uint8_t>(v) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}

inline std::size_t varint_size(std::uint64_t v) {
  std::size_t n = 1;
  for (; v >= 0x80; v >>= 7) ++n;
  return n;
}

inline std::uint64_t xxh64(std::string_view bytes) { return XXH64(bytes.data(), bytes.size(), 0); }

// A complete file around `body` (the sections): correct size field and checksum.
inline std::string seal(std::uint8_t major, std::uint8_t minor, std::uint8_t flags, std::string_view body) {
  std::string out(reinterpret_cast<const char*>(kMagic), 8);
  out.push_back(static_cast<char>(major));
  out.push_back(static_cast<char>(minor));
  out.push_back(static_cast<char>(flags));
  std::uint64_t total = kFixedHeader + 1 + body.size() + kChecksumBytes;
  while (kFixedHeader + varint_size(total) + body.size() + kChecksumBytes != total) ++total;
  put_varint(out, total);
  out.append(body);
  const std::uint64_t sum = xxh64(out);
  for (std::size_t i = 0; i < kChecksumBytes; ++i) out.push_back(static_cast<char>(static_cast<std::uint8_t>(sum >> (8 * i))));
  return out;
}

inline std::string section(std::uint8_t tag, std::string_view payload) {
  std::string out(1, static_cast<char>(tag));
  put_varint(out, payload.size());
  out.append(payload);
  return out;
}

inline std::string counts_payload(std::uint64_t vertices, std::uint64_t faces, std::uint64_t components,
                                  std::uint64_t unreferenced, std::uint8_t flags = 0) {
  std::string out;
  put_varint(out, vertices);
  put_varint(out, faces);
  put_varint(out, components);
  put_varint(out, unreferenced);
  out.push_back(static_cast<char>(flags));
  return out;
}

struct Parts {
  std::uint8_t major = 0, minor = 0, flags = 0;
  std::string body;  // the sections, as in the file
};

// Splits a well-formed container (does not check the checksum); false if it is not one.
inline bool split(std::string_view file, Parts& p) {
  if (file.size() < kFixedHeader + 1 + kChecksumBytes || std::memcmp(file.data(), kMagic, 8) != 0) return false;
  p.major = static_cast<std::uint8_t>(file[8]);
  p.minor = static_cast<std::uint8_t>(file[9]);
  p.flags = static_cast<std::uint8_t>(file[10]);
  std::size_t pos = kFixedHeader;
  while (pos < file.size() && (static_cast<std::uint8_t>(file[pos]) & 0x80)) ++pos;
  ++pos;
  if (pos + kChecksumBytes > file.size()) return false;
  p.body = std::string(file.substr(pos, file.size() - kChecksumBytes - pos));
  return true;
}

// The same file with its size field and checksum made consistent again (so a fuzzer's or a test's
// edit of the body reaches the section parsers); empty if `file` is not shaped like a container.
inline std::string reseal(std::string_view file) {
  Parts p;
  if (!split(file, p)) return {};
  return seal(p.major, p.minor, p.flags, p.body);
}

struct SectionView {
  std::uint8_t tag = 0;
  std::size_t offset = 0;          // of the tag, within the body
  std::size_t payload_offset = 0;  // within the body
  std::string payload;
};

// Sections of a body; stops at the first one that does not fit.
inline std::vector<SectionView> sections(std::string_view body) {
  std::vector<SectionView> out;
  std::size_t pos = 0;
  while (pos < body.size()) {
    SectionView s;
    s.offset = pos;
    s.tag = static_cast<std::uint8_t>(body[pos++]);
    std::uint64_t len = 0;
    for (unsigned shift = 0; pos < body.size() && shift < 64; shift += 7) {
      const auto b = static_cast<std::uint8_t>(body[pos++]);
      len |= std::uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) break;
    }
    if (len > body.size() - pos) break;
    s.payload_offset = pos;
    s.payload = std::string(body.substr(pos, len));
    pos += len;
    out.push_back(std::move(s));
  }
  return out;
}

inline std::string join(const std::vector<SectionView>& secs) {
  std::string body;
  for (const SectionView& s : secs) body += section(s.tag, s.payload);
  return body;
}

}  // namespace qsp::craft
