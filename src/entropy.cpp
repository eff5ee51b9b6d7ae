// Adaptive binary range coder (see format-spec/qsp_format.md, "Entropy coding").
#include "entropy.h"

#include <algorithm>
#include <bit>
#include <string>

#include "qsp/error.h"

namespace qsp {
namespace {

constexpr std::uint32_t kTop = RangeEncoder::kTop;

}  // namespace

CompactEnd compact_end(std::uint64_t low, std::uint32_t range) {
  const std::uint64_t lw = low & 0xFFFFFFFFu;  // multiples of 2^(8k), k <= 4, agree modulo 2^32
  for (int k = 4; k > 0; --k) {
    const std::uint64_t unit = std::uint64_t{1} << (8 * k);
    const std::uint64_t value = (lw + unit - 1) & ~(unit - 1);
    if (value < lw + range) return {value, k};
  }
  return {lw, 0};  // not reached: range >= 2^24 holds a multiple of 2^24
}

void RangeEncoder::shift_low() {
  if (static_cast<std::uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
    auto carry = static_cast<std::uint8_t>(low_ >> 32);
    std::uint8_t temp = cache_;
    do {
      if (skip_first_) {
        skip_first_ = false;  // LZMA's first byte, always 0, is left out
      } else {
        out_.push_back(static_cast<char>(static_cast<std::uint8_t>(temp + carry)));
      }
      temp = 0xFF;
    } while (--cache_size_ != 0);
    cache_ = static_cast<std::uint8_t>(low_ >> 24);
  }
  ++cache_size_;
  low_ = (low_ & 0x00FFFFFFu) << 8;
}

void RangeEncoder::normalize() {
  while (range_ < kTop) {
    range_ <<= 8;
    shift_low();
  }
}

void RangeDecoder::normalize() {
  while (range_ < kTop) {
    range_ <<= 8;
    code_ = (code_ << 8) | next_byte();
  }
}

void RangeEncoder::finish() {
  // The value in [low, low + range) with the most trailing zero bytes (k of the 4 bytes of low): any
  // value of the final interval decodes the same symbols, and zeros need not be written.
  const CompactEnd end = compact_end(low_, range_);
  low_ += end.value - (low_ & 0xFFFFFFFFu);  // the same multiples of 2^(8k) modulo 2^32
  const int k = end.zeros;
  for (int i = 0; i < 5; ++i) shift_low();
  // The 5 shifts wrote low's 4 bytes last (after the cache byte, so never the skipped first one); its
  // low k bytes are 0.
  out_.resize(out_.size() - static_cast<std::size_t>(k));
}

RangeDecoder::RangeDecoder(std::string_view bytes, std::uint64_t base_offset, const char* what)
    : bytes_(bytes), base_offset_(base_offset), what_(what) {
  for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next_byte();
  check_code();
}

// code < range holds for every stream the encoder writes: code is the stream's value minus low. A
// decision keeps it; a raw bit on an odd range, or the first four bytes, can break it, and from such a
// state a few byte strings the encoder never writes would decode to its symbols.
void RangeDecoder::check_code() const {
  if (code_ >= range_) {
    throw Error(ErrorCode::kFormat, std::string(what_) +
                                        ": value outside the coder's interval (at byte offset " +
                                        std::to_string(base_offset_ + std::min(pos_, bytes_.size())) + ")");
  }
}

std::uint8_t RangeDecoder::byte_past_end() {
  if (pos_ < bytes_.size() + 4) {
    ++pos_;
    return 0;  // a zero the compact flush left out
  }
  throw Error(ErrorCode::kFormat, std::string(what_) + " ends too early: needs more than its " +
                                      std::to_string(bytes_.size()) + " bytes (at byte offset " +
                                      std::to_string(base_offset_ + bytes_.size()) + ")");
}

void RangeDecoder::finish() const {
  // The last 4 bytes read (the constructor reads 4), the zeros past the end included.
  std::uint32_t window = 0;
  for (std::size_t k = pos_ - 4; k < pos_; ++k)
    window = (window << 8) | (k < bytes_.size() ? static_cast<std::uint8_t>(bytes_[k]) : 0u);
  // The final interval starts at (last 4 bytes read) - code; the stream must end on the value the
  // encoder picks in it, with exactly its trailing zero bytes left out.
  const CompactEnd end = compact_end(static_cast<std::uint32_t>(window - code_), range_);
  if (pos_ == bytes_.size() + static_cast<std::size_t>(end.zeros) &&
      end.value % (std::uint64_t{1} << 32) == window)
    return;
  if (pos_ < bytes_.size()) {
    throw Error(ErrorCode::kFormat, std::string(what_) + " does not end where its symbols end (" +
                                        std::to_string(bytes_.size() - pos_) +
                                        " bytes unused, at byte offset " +
                                        std::to_string(base_offset_ + pos_) + ")");
  }
  throw Error(ErrorCode::kFormat,
              std::string(what_) + " does not end as the encoder ends it (its last bytes, at byte offset " +
                  std::to_string(base_offset_ + bytes_.size()) + ")");
}

// The tail's models are made when a value first needs them: most models never code a value above 511,
// and making 1024 models for each of them was most of the cost of starting a small section's coder.
// The tree is made at its first use: most of a coder's models (a context per component and bucket) code
// few values or none, and making each tree up front was a tenth of compressing a small mesh's UVs.
IntModel::IntModel() = default;

void IntModel::encode(RangeEncoder& enc, std::uint32_t value) {
  std::uint32_t v = value + 1;  // >= 1; value <= 2^32 - 2 by contract
  unsigned n = static_cast<unsigned>(std::bit_width(v)) - 1;
  for (unsigned i = 0; i < n; ++i) enc.encode_bit(prefix_[i], 1);
  if (n < kMaxBits) enc.encode_bit(prefix_[n], 0);
  if (n <= kTreeBits) {
    if (n > 0 && tree_.empty()) tree_.resize(std::size_t{2} << kTreeBits);
    std::uint32_t node = 1;
    for (unsigned i = n; i-- > 0;) {
      unsigned bit = (v >> i) & 1u;
      enc.encode_bit(tree_[(std::size_t{1} << n) + node - 1], bit);
      node = 2 * node + bit;
    }
  } else {
    if (tail_.empty()) tail_.resize(32 * 32);
    for (unsigned i = n; i-- > 0;) enc.encode_bit(tail_[32 * n + i], (v >> i) & 1u);
  }
}

std::uint32_t IntModel::decode(RangeDecoder& dec) {
  unsigned n = 0;
  while (n < kMaxBits && dec.decode_bit(prefix_[n]) == 1) ++n;
  std::uint32_t v = 1;
  if (n <= kTreeBits) {
    if (n > 0 && tree_.empty()) tree_.resize(std::size_t{2} << kTreeBits);
    std::uint32_t node = 1;
    for (unsigned i = 0; i < n; ++i) {
      unsigned bit = dec.decode_bit(tree_[(std::size_t{1} << n) + node - 1]);
      node = 2 * node + bit;
      v = (v << 1) | bit;
    }
  } else {
    if (tail_.empty()) tail_.resize(32 * 32);
    for (unsigned i = n; i-- > 0;) v = (v << 1) | dec.decode_bit(tail_[32 * n + i]);
  }
  return v - 1;  // every prefix the decoder accepts gives v in [1, 2^32 - 1]
}

}  // namespace qsp
