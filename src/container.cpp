// The .qsp container: see container.h and format-spec/qsp_format.md, "File structure" and "Sections".
#include "container.h"

// Header-only (XXH_INLINE_ALL): the installed library needs no xxhash to link against.
#define XXH_INLINE_ALL
#include <xxhash.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iterator>

#include "bytes.h"
#include "qsp/error.h"

namespace qsp::container {
namespace {

std::string at(std::uint64_t offset) { return " (at byte offset " + std::to_string(offset) + ")"; }

[[noreturn]] void format_error(const std::string& what, std::uint64_t offset) {
  throw Error(ErrorCode::kFormat, what + at(offset));
}

std::string version(std::uint8_t major, std::uint8_t minor) {
  return std::to_string(major) + "." + std::to_string(minor);
}

// The magic number, with what the usual damage in transit did to it.
void check_magic(std::string_view file) {
  const std::size_t n = file.size();
  if (std::memcmp(file.data(), kMagic, std::min<std::size_t>(n, 8)) != 0) {
    std::string why = "not a .qsp file (bad magic number)";
    if (n >= 6 && static_cast<std::uint8_t>(file[0]) == 0x09 && file.substr(1, 3) == "QSP") {
      why += "; the high bit of byte 0 was cleared, as by a 7-bit transfer";
    } else if (n >= 6 && static_cast<std::uint8_t>(file[0]) == 0x89 && file.substr(1, 3) == "QSP") {
      why += "; the line-ending bytes were changed, as by a text-mode transfer or CR LF conversion";
    }
    format_error(why, 0);
  }
  if (n < 8) format_error("truncated: file ends inside the magic number", n);
}

void check_version(std::uint8_t major, std::uint8_t minor) {
  if (major == kFormatMajor) return;
  std::string why = "file is .qsp format " + version(major, minor);
  if (major > kFormatMajor) {
    why += "; this qsp reads format " + std::to_string(kFormatMajor) + ".x (upgrade qsp)";
  } else {
    why += ", a development version (before 3.0) that this qsp does not read";
  }
  throw Error(ErrorCode::kVersion, why + at(8));
}

}  // namespace

std::string tag_name(std::uint8_t tag) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02x", tag);
  return buf;
}

const Section* File::find(std::uint8_t tag) const {
  for (const Section& s : sections)
    if (s.tag == tag) return &s;
  return nullptr;
}

std::uint64_t checksum(std::string_view bytes) { return XXH64(bytes.data(), bytes.size(), 0); }

File parse(std::string_view file) {
  check_magic(file);
  File f;
  const std::size_t n = file.size();
  ByteReader r(file.substr(0, n), 0);
  r.take(8, "magic number");
  f.major = r.u8("version");
  f.minor = r.u8("version");
  check_version(f.major, f.minor);
  const std::uint8_t encoder = r.u8("encoder byte");
  const std::uint64_t declared = r.varint("file size");
  if (declared > n) {
    format_error(
        "truncated: header declares " + std::to_string(declared) + " bytes, file has " + std::to_string(n),
        n);
  }
  if (declared < n)
    format_error(std::to_string(n - declared) + " trailing bytes after the end of the .qsp", declared);
  if (n < r.pos() + kChecksumBytes) format_error("truncated: no room for the checksum", n);
  const std::size_t body_end = n - kChecksumBytes;
  std::uint64_t stored = 0;
  for (std::size_t i = 0; i < kChecksumBytes; ++i)
    stored |= std::uint64_t{static_cast<std::uint8_t>(file[body_end + i])} << (8 * i);
  const std::uint64_t actual = checksum(file.substr(0, body_end));
  if (stored != actual) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "checksum mismatch: stored %016llx, computed %016llx",
                  static_cast<unsigned long long>(stored), static_cast<unsigned long long>(actual));
    throw Error(ErrorCode::kChecksum, std::string(buf) + " (file is corrupt)" + at(body_end));
  }
  // After the checksum: a flipped bit is then reported as corruption, not as a reserved bit.
  if (encoder & ~kLevelMask) format_error("reserved encoder byte bits are set (must be zero)", 10);
  if ((encoder & kLevelMask) > kMaxLevelValue)
    format_error("compression level " + std::to_string(encoder & kLevelMask) + " is not 0 to 9", 10);
  f.level = encoder & kLevelMask;

  ByteReader s(file.substr(r.pos(), body_end - r.pos()), r.pos());
  int last = -1;
  while (s.left() > 0) {
    Section sec;
    sec.offset = s.offset();
    sec.tag = s.u8("section tag");
    const std::uint64_t len = s.varint("section length");
    sec.payload_offset = s.offset();
    sec.payload = s.take(len, "section");
    if ((sec.tag & ~kOptionalBit) == 0) format_error("invalid section tag " + tag_name(sec.tag), sec.offset);
    if (sec.tag <= last) {
      format_error("section " + tag_name(sec.tag) + " after section " +
                       tag_name(static_cast<std::uint8_t>(last)) +
                       " (sections come in increasing tag order, each once)",
                   sec.offset);
    }
    const auto kind = std::find_if(std::begin(kSections), std::end(kSections),
                                   [&](const SectionKind& k) { return k.tag == sec.tag; });
    const bool known = kind != std::end(kSections) || (sec.tag & kOptionalBit);
    if (kind != std::end(kSections) && held_to_minor(*kind) && f.minor < kind->minor)
      format_error("section " + tag_name(sec.tag) + " (" + std::string(kind->name) + ") is format " +
                       version(kFormatMajor, kind->minor) + "'s, and the file says it is " +
                       version(f.major, f.minor),
                   sec.offset);
    // The comments and coded comments sections hold the same lines: a file holds one of them at most.
    if (sec.tag == kTagCodedComments && f.find(kTagComments) != nullptr)
      format_error("section 0x85 (coded comments) beside section 0x81 (comments)", sec.offset);
    if (!known) {
      const std::string what = "section " + tag_name(sec.tag) +
                               " is required but unknown to this qsp, which reads format " +
                               version(kFormatMajor, kFormatMinor);
      if (f.minor > kFormatMinor) throw Error(ErrorCode::kVersion, what + " (upgrade qsp)" + at(sec.offset));
      format_error(what + ", and the file says it is " + version(f.major, f.minor), sec.offset);
    }
    if (sec.tag > kTagCounts && last < kTagCounts)
      format_error("required section 1 (counts) is missing", sec.offset);
    if (sec.tag > kTagTopology && last < kTagTopology)
      format_error("required section 2 (topology) is missing", sec.offset);
    if (sec.tag > kTagGeometry && last < kTagGeometry)
      format_error("required section 3 (geometry) is missing", sec.offset);
    last = sec.tag;
    f.sections.push_back(sec);
  }
  if (last < kTagGeometry) {
    format_error("required section " +
                     std::to_string(last < kTagCounts     ? 1
                                    : last < kTagTopology ? 2
                                                          : 3) +
                     (last < kTagCounts     ? " (counts)"
                      : last < kTagTopology ? " (topology)"
                                            : " (geometry)") +
                     " is missing",
                 body_end);
  }
  return f;
}

void put_section(std::string& out, std::uint8_t tag, std::string_view payload) {
  out.push_back(static_cast<char>(tag));
  put_varint(out, payload.size());
  out.append(payload);
}

std::string seal(std::uint8_t major, std::uint8_t minor, std::uint8_t encoder, std::string_view sections) {
  std::string out(reinterpret_cast<const char*>(kMagic), 8);
  out.push_back(static_cast<char>(major));
  out.push_back(static_cast<char>(minor));
  out.push_back(static_cast<char>(encoder));
  // The size field counts itself: the shortest varint length whose value is consistent.
  std::uint64_t total = kFixedHeader + 1 + sections.size() + kChecksumBytes;
  while (kFixedHeader + varint_size(total) + sections.size() + kChecksumBytes != total) ++total;
  put_varint(out, total);
  out.append(sections);
  put_le(out, checksum(out), static_cast<int>(kChecksumBytes));
  return out;
}

std::string with_section(std::string_view file, std::uint8_t tag, std::string_view payload,
                         std::uint8_t minor) {
  const File f = parse(file);
  std::string body;
  bool put = false;
  for (const Section& s : f.sections) {
    if (!put && s.tag >= tag) put_section(body, tag, payload), put = true;
    if (s.tag != tag) put_section(body, s.tag, s.payload);
  }
  if (!put) put_section(body, tag, payload);
  return seal(f.major, std::max(f.minor, minor), f.level, body);
}

}  // namespace qsp::container
