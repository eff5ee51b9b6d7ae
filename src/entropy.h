// The adaptive binary range coder every entropy-coded .qsp stream uses (internal). Exactly specified in
// format-spec/qsp_format.md ("Entropy coding"): a change here is a format change.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace qsp {

// Probability that the next bit is 0, in units of 2^-16: the mean of a fast (rate 1/16) and a slow
// (rate 1/128) estimate, so it follows drifting statistics and is still precise on long streams.
// While young, both rates start at 1/2 and slow down with the bits seen (1/2, 1/4, 1/4, 1/8 x4, ...),
// about a running average: schematics are small (hundreds of symbols per context), and this warm-up
// saves ~20% on them over fixed rates.
struct BitModel {
  std::uint16_t fast = 32768, slow = 32768;
  std::uint8_t seen = 0;  // counts up to kMature only (see learn)
  std::uint32_t p0() const { return (std::uint32_t{fast} + slow) >> 1; }
};

// From this many bits seen on, nothing depends on the count: the rates are 1/16 and 1/128, and the
// geometry section's mixed decisions use the model alone. So the count stops there (the format
// describes a count saturating at 255, which gives the same probabilities).
inline constexpr unsigned kMature = 64;

// How learn() moves a model's estimates: kBranch branches on the bit (an encoder, which knows its bits
// ahead); kMask takes both ways by masks (a decoder, which has only just computed the bit: a
// mispredicted branch stalled the next decision, whose model the bit picks; a 10% faster decode of
// residuals); kSelect by conditional selects (the logistic decisions' four models: 6% faster than
// either there). Masks, as a compiler may turn a select back into a branch.
enum class Learn { kBranch, kSelect, kMask };

// Moves m's estimates towards `bit` by 2^-fast_shift and 2^-slow_shift.
template <Learn kHow>
inline void adapt(BitModel& m, unsigned bit, unsigned fast_shift, unsigned slow_shift) {
  if constexpr (kHow == Learn::kMask) {
    const std::uint32_t fast = m.fast, slow = m.slow;
    // The distance to 0 (bit 1) or 65536 (bit 0), shifted, then subtracted (bit 1) or added.
    const std::uint32_t mask = 0u - bit;
    const std::uint32_t df = (65536u - fast + ((2 * fast - 65536u) & mask)) >> fast_shift;
    const std::uint32_t ds = (65536u - slow + ((2 * slow - 65536u) & mask)) >> slow_shift;
    m.fast = static_cast<std::uint16_t>(fast + ((df ^ mask) - mask));
    m.slow = static_cast<std::uint16_t>(slow + ((ds ^ mask) - mask));
  } else if constexpr (kHow == Learn::kSelect) {
    const std::uint32_t fast = m.fast, slow = m.slow;
    const std::uint32_t df = (bit ? fast : 65536u - fast) >> fast_shift;
    const std::uint32_t ds = (bit ? slow : 65536u - slow) >> slow_shift;
    m.fast = static_cast<std::uint16_t>(bit ? fast - df : fast + df);
    m.slow = static_cast<std::uint16_t>(bit ? slow - ds : slow + ds);
  } else if (bit) {
    m.fast = static_cast<std::uint16_t>(m.fast - (m.fast >> fast_shift));
    m.slow = static_cast<std::uint16_t>(m.slow - (m.slow >> slow_shift));
  } else {
    m.fast = static_cast<std::uint16_t>(m.fast + ((65536u - m.fast) >> fast_shift));
    m.slow = static_cast<std::uint16_t>(m.slow + ((65536u - m.slow) >> slow_shift));
  }
}

// learn() for a model known to have seen kMature bits: its count no longer moves, its shifts are fixed.
template <Learn kHow = Learn::kBranch>
inline void learn_mature(BitModel& m, unsigned bit) {
  adapt<kHow>(m, bit, 4, 7);
}

// What coding `bit` teaches model m (the rates above). Inline: the geometry section's logistic
// decisions update four models a bit. A mature model, the common case, takes fixed shifts.
template <Learn kHow = Learn::kBranch>
inline void learn(BitModel& m, unsigned bit) {
  if (m.seen >= kMature) return learn_mature<kHow>(m, bit);
  const auto warm = static_cast<unsigned>(std::bit_width(static_cast<unsigned>(m.seen) + 1u));
  adapt<kHow>(m, bit, warm < 4 ? warm : 4, warm < 7 ? warm : 7);
  ++m.seen;
}

// How a stream ends ("Compact ends"): LZMA's range coder without its first byte (always 0), and a flush
// that ends on the value of the final interval [low, low + range) (range >= 2^24) with the most
// trailing zero bytes, those bytes left out; the decoder reads them back as zeros. The number of
// those bytes k (3 or 4), and that value's low 32 bits plus 2^32 if it carries.
struct CompactEnd {
  std::uint64_t value;
  int zeros;
};
CompactEnd compact_end(std::uint64_t low, std::uint32_t range);

// LZMA-style range encoder (32-bit range, carry propagation through a cached byte), appending to `out`.
class RangeEncoder {
 public:
  explicit RangeEncoder(std::string& out) : out_(out) {}
  // Inline, as encode_p0: a call per decision was a fifth of the geometry coder thread's time.
  void encode_bit(BitModel& m, unsigned bit) {
    encode_p0(m.p0(), bit);
    learn(m, bit);
  }
  // `count` (<= 32) bits of `value`, most significant first, each with probability 1/2. Inline: the
  // geometry section codes a few after most residuals, often none.
  void encode_raw(std::uint32_t value, unsigned count) {
    for (unsigned i = count; i-- > 0;) {
      range_ >>= 1;
      low_ += range_ & (0u - ((value >> i) & 1u));  // a mask: a branch on a random bit mispredicts
      if (range_ < kTop) normalize();
    }
  }
  // One bit with probability p0 / 2^16 of a 0 (1 <= p0 <= 65535), from a model outside this class.
  void encode_p0(std::uint32_t p0, unsigned bit) {
    const std::uint32_t bound = (range_ >> kProbBits) * p0;
    if (bit == 0) {
      range_ = bound;
    } else {
      low_ += bound;
      range_ -= bound;
    }
    if (range_ < kTop) normalize();
  }
  // Writes the final bytes; call exactly once, after the last symbol.
  void finish();

  static constexpr unsigned kProbBits = 16;
  static constexpr std::uint32_t kTop = 1u << 24;

 private:
  void normalize();  // shifts bytes out while range < kTop
  void shift_low();
  std::string& out_;
  bool skip_first_ = true;  // LZMA's first byte (always 0) is not written
  std::uint64_t low_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint8_t cache_ = 0;
  std::uint64_t cache_size_ = 1;
};

// Inverse of RangeEncoder over exactly `bytes`. Reading past the end (more than the 4 zero bytes the
// flush may leave out) throws Error(kFormat) naming `what` and the absolute offset (`base_offset` +
// position), so a hostile stream fails as soon as it runs out; finish() checks that every byte was
// used and the stream ended as the encoder ends it. Safe on untrusted input.
class RangeDecoder {
 public:
  RangeDecoder(std::string_view bytes, std::uint64_t base_offset, const char* what);
  // Inline, as decode_p0: a call per decision was a tenth of decoding a mesh's geometry.
  unsigned decode_bit(BitModel& m) {
    const unsigned bit = decode_p0(m.p0());
    learn<Learn::kMask>(m, bit);
    return bit;
  }
  // Inline, as encode_raw.
  std::uint32_t decode_raw(unsigned count) {
    std::uint32_t value = 0;
    for (unsigned i = 0; i < count; ++i) {
      range_ >>= 1;
      const std::uint32_t bit = code_ >= range_;
      code_ -= range_ & (0u - bit);  // a mask: a branch on a random bit mispredicts
      if (code_ >= range_) [[unlikely]]
        check_code();  // throws
      value = (value << 1) | bit;
      if (range_ < RangeEncoder::kTop) normalize();
    }
    return value;
  }
  // Without a branch on the bit, as learn<Learn::kMask>.
  unsigned decode_p0(std::uint32_t p0) {
    const std::uint32_t bound = (range_ >> RangeEncoder::kProbBits) * p0;
    const unsigned bit = code_ >= bound;
    const std::uint32_t mask = 0u - bit;  // masks, not selects, which a compiler may make branches
    code_ -= bound & mask;
    range_ = bound + ((range_ - 2 * bound) & mask);
    if (range_ < RangeEncoder::kTop) normalize();
    return bit;
  }
  void finish() const;
  // Absolute file offset of the next unread byte (for error messages).
  std::uint64_t offset() const { return base_offset_ + pos_; }

 private:
  void normalize();  // reads bytes in while range < kTop
  std::uint8_t next_byte() {
    return pos_ < bytes_.size() ? static_cast<std::uint8_t>(bytes_[pos_++]) : byte_past_end();
  }
  std::uint8_t byte_past_end();
  void check_code() const;
  std::string_view bytes_;
  std::uint64_t base_offset_;
  const char* what_;
  std::size_t pos_ = 0;  // may pass bytes_.size() by up to 4 (zeros the flush left out)
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint32_t code_ = 0;
};

// Adaptive Exp-Golomb model for unsigned integers 0 .. 2^32 - 2. Codes n = bit length of (v + 1)
// minus 1 in unary (one context per position; no terminator when n = 31), then the n bits of v + 1
// below its leading one, most significant first: through a full binary context tree when n <= 8 (so
// any distribution of small values is learnt exactly), otherwise one context per (n, position) (so
// e.g. "always a multiple of 4" is still learnt).
class IntModel {
 public:
  static constexpr unsigned kMaxBits = 31;
  static constexpr unsigned kTreeBits = 8;
  IntModel();
  void encode(RangeEncoder& enc, std::uint32_t value);
  // Throws Error(kFormat) if the prefix is longer than any value the encoder can write.
  std::uint32_t decode(RangeDecoder& dec);

 private:
  std::array<BitModel, kMaxBits> prefix_;
  std::vector<BitModel> tree_;  // index (1 << n) + node - 1, node = 1 then 2*node + bit
  std::vector<BitModel> tail_;  // index 32 * n + position, for n > kTreeBits (empty until one comes)
};

// Zigzag map of a signed value to unsigned (0, -1, 1, -2, ... -> 0, 1, 2, 3, ...).
inline std::uint32_t zigzag(std::int64_t v) {
  return static_cast<std::uint32_t>(v >= 0 ? 2 * v : -2 * v - 1);
}
inline std::int64_t unzigzag(std::uint32_t u) {
  return (u & 1u) ? -static_cast<std::int64_t>(u >> 1) - 1 : static_cast<std::int64_t>(u >> 1);
}

}  // namespace qsp
