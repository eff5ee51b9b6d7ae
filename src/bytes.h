// Bytes in and out, as every part of a .qsp file spells them (format-spec/qsp_format.md,
// "Conventions"): little-endian integers and minimal LEB128 varints, and a bounds-checked reader whose
// errors say what it was reading and at which absolute byte offset of the file.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include "qsp/error.h"

namespace qsp {

inline void put_u8(std::string& out, std::uint8_t v) { out.push_back(static_cast<char>(v)); }

// The low `bytes` bytes of `v`, least significant first.
inline void put_le(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>(static_cast<std::uint8_t>(v >> (8 * i))));
}

// Unsigned LEB128: 7 bits a byte, least significant group first, bit 7 on every byte but the last.
inline void put_varint(std::string& out, std::uint64_t v) {
  for (; v >= 0x80; v >>= 7) out.push_back(static_cast<char>(static_cast<std::uint8_t>(v) | 0x80));
  out.push_back(static_cast<char>(v));
}

inline std::size_t varint_size(std::uint64_t v) {
  std::size_t n = 1;
  for (; v >= 0x80; v >>= 7) ++n;
  return n;
}

// Reads `bytes`, which begin at absolute file offset `base`. Every failure is Error(kFormat) with the
// message "<context>: <what went wrong> (at byte offset N)" (no "<context>: " when it is empty), N the
// offset of the field being read, so a caller never re-wraps it. Safe on untrusted input.
class ByteReader {
 public:
  ByteReader(std::string_view bytes, std::uint64_t base, std::string context = {})
      : bytes_(bytes), base_(base), context_(std::move(context)) {}

  std::size_t left() const { return bytes_.size() - pos_; }
  std::size_t pos() const { return pos_; }
  std::uint64_t offset() const { return base_ + pos_; }  // absolute offset of the next byte

  std::uint8_t u8(const char* what) {
    if (pos_ >= bytes_.size()) fail(std::string("truncated: no room for ") + what);
    return static_cast<std::uint8_t>(bytes_[pos_++]);
  }
  // `n` (<= 8) bytes, little-endian.
  std::uint64_t le(int n, const char* what) {
    if (left() < static_cast<std::size_t>(n)) fail(std::string("truncated: no room for ") + what);
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t{static_cast<std::uint8_t>(bytes_[pos_++])} << (8 * i);
    return v;
  }
  // A varint of at most 64 bits in its one minimal form (a unique encoding keeps corruption visible).
  std::uint64_t varint(const char* what) {
    const std::uint64_t start = offset();
    std::uint64_t v = 0;
    for (unsigned shift = 0;; shift += 7) {
      const std::uint8_t b = u8(what);
      if (shift == 63 && b > 1) fail_at(std::string(what) + " does not fit in 64 bits", start);
      v |= std::uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) {
        if (b == 0 && shift != 0) fail_at(std::string(what) + " is not minimally encoded", start);
        return v;
      }
    }
  }
  std::string_view take(std::uint64_t n, const char* what) {
    if (n > left()) {
      fail(std::string(what) + " declares " + std::to_string(n) + " bytes but only " +
           std::to_string(left()) + " remain");
    }
    const std::string_view s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  std::string_view rest() {
    const std::string_view s = bytes_.substr(pos_);
    pos_ = bytes_.size();
    return s;
  }

  [[noreturn]] void fail(const std::string& what) const { fail_at(what, offset()); }
  [[noreturn]] void fail_at(const std::string& what, std::uint64_t at) const {
    throw Error(ErrorCode::kFormat, (context_.empty() ? "" : context_ + ": ") + what + " (at byte offset " +
                                        std::to_string(at) + ")");
  }

 private:
  std::string_view bytes_;
  std::uint64_t base_;
  std::string context_;
  std::size_t pos_ = 0;
};

}  // namespace qsp
