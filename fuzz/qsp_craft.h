// Taking .qsp containers apart and putting them back together by hand, for the fuzzers and
// tests/test_hostile.cpp. The container itself (magic, version, encoder byte, size field, sections,
// XXH64) is the library's own src/container.h, which seals what is built here; these helpers only add
// what crafting needs: splitting a file that may be malformed without checking it.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "bytes.h"
#include "container.h"

namespace qsp::craft {

using container::kChecksumBytes;
using container::kFixedHeader;
using container::kMagic;
using container::kTagCounts;
using container::kTagGeometry;
using container::kTagOrder;
using container::kTagTopology;
using qsp::put_varint;

// A complete file around `body` (the sections): correct size field and checksum.
inline std::string seal(std::uint8_t major, std::uint8_t minor, std::uint8_t encoder, std::string_view body) {
  return container::seal(major, minor, encoder, body);
}

inline std::string section(std::uint8_t tag, std::string_view payload) {
  std::string out;
  container::put_section(out, tag, payload);
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
  std::uint8_t major = 0, minor = 0, encoder = 0;
  std::string body;  // the sections, as in the file
};

// Splits a container-shaped file (does not check the checksum); false if it is not one. The header
// and the size field are read with the library's ByteReader, so a size field that is not one minimal
// varint makes the file not container-shaped.
inline bool split(std::string_view file, Parts& p) {
  if (file.size() < kFixedHeader + 1 + kChecksumBytes || std::memcmp(file.data(), kMagic, 8) != 0)
    return false;
  ByteReader r(file.substr(0, file.size() - kChecksumBytes), 0);
  try {
    r.take(sizeof kMagic, "magic number");
    p.major = r.u8("version");
    p.minor = r.u8("version");
    p.encoder = r.u8("encoder byte");
    r.varint("file size");
  } catch (const Error&) {
    return false;
  }
  p.body = std::string(r.rest());
  return true;
}

// The same file with its size field and checksum made consistent again (so a fuzzer's or a test's
// edit of the body reaches the section parsers); empty if `file` is not shaped like a container.
inline std::string reseal(std::string_view file) {
  Parts p;
  if (!split(file, p)) return {};
  return seal(p.major, p.minor, p.encoder, p.body);
}

struct SectionView {
  std::uint8_t tag = 0;
  std::size_t offset = 0;          // of the tag, within the body
  std::size_t payload_offset = 0;  // within the body
  std::string payload;
};

// Sections of a body; stops at the first one that does not fit (its length runs past the end or is
// not one minimal varint, as ByteReader reads it).
inline std::vector<SectionView> sections(std::string_view body) {
  std::vector<SectionView> out;
  ByteReader r(body, 0);
  try {
    while (r.left() > 0) {
      SectionView s;
      s.offset = r.pos();
      s.tag = r.u8("section tag");
      const std::uint64_t len = r.varint("section length");
      s.payload_offset = r.pos();
      s.payload = std::string(r.take(len, "section"));
      out.push_back(std::move(s));
    }
  } catch (const Error&) {
  }
  return out;
}

inline std::string join(const std::vector<SectionView>& secs) {
  std::string body;
  for (const SectionView& s : secs) body += section(s.tag, s.payload);
  return body;
}

}  // namespace qsp::craft
