// The range coder every .qsp stream uses (src/entropy.h, format-spec/qsp_format.md "Entropy coding"),
// and the geometry section's mixed decisions on top of it (src/geometry_model.h).
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "entropy.h"
#include "geometry_model.h"
#include "qsp/error.h"

namespace qsp {
namespace {

// ---- Entropy coder ----

TEST(Entropy, BitsAndIntegersRoundTrip) {
  std::mt19937 rng(7);
  std::vector<unsigned> bits;
  std::vector<std::uint32_t> ints;
  for (int i = 0; i < 20000; ++i) {
    bits.push_back(rng() % 10 == 0);
    std::uint32_t mag = rng() % 33;
    ints.push_back(mag == 32 ? 0xFFFFFFFEu : static_cast<std::uint32_t>(rng() & ((1ull << mag) - 1)));
  }
  std::string out;
  RangeEncoder enc(out);
  BitModel bm[3];
  IntModel im;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    enc.encode_bit(bm[i % 3], bits[i]);
    im.encode(enc, ints[i]);
    enc.encode_raw(ints[i] & 0xFFFF, 16);
  }
  enc.finish();
  RangeDecoder dec(out, 0, "test stream");
  BitModel dm[3];
  IntModel di;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    ASSERT_EQ(dec.decode_bit(dm[i % 3]), bits[i]);
    ASSERT_EQ(di.decode(dec), ints[i]);
    ASSERT_EQ(dec.decode_raw(16), ints[i] & 0xFFFF);
  }
  EXPECT_NO_THROW(dec.finish());
}

TEST(Entropy, SkewedBitsCostLittle) {
  std::string out;
  RangeEncoder enc(out);
  BitModel m;
  for (int i = 0; i < 100000; ++i) enc.encode_bit(m, 0);
  enc.finish();
  EXPECT_LT(out.size(), 60u);  // ~0.003 bits each once learnt
}

// A mixed decision (the geometry section's residual lengths without logistic mixing) round-trips and leans on
// whichever model has seen more: a fresh specific model (one per symbol here) coded alone pays ~1 bit each
// time, mixed with a trained general one far less.
TEST(Entropy, MixedDecisionsLeanOnTheExperiencedModel) {
  std::mt19937 rng(3);
  std::vector<unsigned> bits(4000);
  for (unsigned& b : bits) b = rng() % 8 == 0;
  auto code = [&](bool mix) {
    std::string out;
    RangeEncoder enc(out);
    BitModel general;
    std::vector<BitModel> specific(bits.size());
    for (std::size_t i = 0; i < bits.size(); ++i)
      mix ? encode_mixed(enc, specific[i], general, bits[i]) : enc.encode_bit(specific[i], bits[i]);
    enc.finish();
    return out;
  };
  const std::string alone = code(false), mixed = code(true);
  EXPECT_GT(alone.size(), bits.size() / 8 * 9 / 10);  // ~1 bit per decision
  EXPECT_LT(mixed.size(), bits.size() / 8 * 7 / 10);  // entropy of 1/8 is 0.54 bits
  RangeDecoder dec(mixed, 0, "test stream");
  BitModel general;
  std::vector<BitModel> specific(bits.size());
  for (std::size_t i = 0; i < bits.size(); ++i)
    ASSERT_EQ(decode_mixed(dec, specific[i], general), bits[i]) << i;
  EXPECT_NO_THROW(dec.finish());
}

// Once the specific model has seen 64 bits it codes alone: the same bytes as a single-model stream,
// and the general model is left as it was.
TEST(Entropy, MatureModelsCodeAlone) {
  BitModel trained;
  {
    std::string scratch;
    RangeEncoder warm(scratch);
    for (int i = 0; i < 64; ++i) warm.encode_bit(trained, i % 5 == 0);
  }
  std::mt19937 rng(5);
  std::vector<unsigned> bits(500);
  for (unsigned& b : bits) b = rng() % 3 == 0;
  std::string single, mixed;
  RangeEncoder one(single), two(mixed);
  BitModel a = trained, b = trained, general;
  for (unsigned bit : bits) {
    one.encode_bit(a, bit);
    encode_mixed(two, b, general, bit);
  }
  one.finish();
  two.finish();
  EXPECT_EQ(single, mixed);
  EXPECT_EQ(general.seen, 0);
}

TEST(Entropy, DecoderRefusesShortAndLongStreams) {
  std::string out;
  RangeEncoder enc(out);
  BitModel m;
  for (int i = 0; i < 1000; ++i) enc.encode_bit(m, i % 3 == 0);
  enc.finish();
  // Whether `s` decodes to the encoder's 1000 bits; false for other bits, a throw for a refusal.
  auto run = [](std::string_view s) {
    RangeDecoder dec(s, 100, "test stream");
    BitModel dm;
    bool same = true;
    for (int i = 0; i < 1000; ++i) same &= dec.decode_bit(dm) == (i % 3 == 0 ? 1u : 0u);
    dec.finish();
    return same;
  };
  EXPECT_TRUE(run(out));
  // A prefix is refused, or (compact ends read zeros past the end) decodes to other bits.
  for (std::size_t n = 0; n < out.size(); ++n) {
    try {
      EXPECT_FALSE(run(std::string_view(out).substr(0, n))) << n;
    } catch (const Error&) {
    }
  }
  EXPECT_THROW(run(out + std::string(1, '\0')), Error);
}

// Every single-byte change, cut or append of a stream either decodes other symbols or is refused: the
// encoder's bytes are the only ones that give its symbols. (Before the decoder checked code < range,
// `ff ff ff f9 16` passed for a stream written as `ff ff ff f8 16`.)
TEST(Entropy, OnlyTheEncodersBytesGiveItsSymbols) {
  struct Symbol {
    int model;  // 0, 1: a decision through that model; -n: n raw bits
    std::uint32_t value;
  };
  std::vector<std::vector<Symbol>> cases = {
      {{-8, 0xFF}},
      {{1, 1}, {-6, 63}, {0, 1}, {0, 1}, {-6, 63}, {1, 1}, {-4, 15}, {-8, 255}, {-5, 31}, {0, 1}}};
  std::mt19937 rng(17);
  for (int c = 0; c < 40; ++c) {
    std::vector<Symbol> sy(1 + rng() % 24);
    for (Symbol& x : sy) {
      const int kind = static_cast<int>(rng() % 3);
      const int n = 1 + static_cast<int>(rng() % 12);
      x = kind < 2 ? Symbol{kind, rng() % 5 == 0 ? 1u : 0u}
                   : Symbol{-n, static_cast<std::uint32_t>(rng()) & ((1u << n) - 1)};
    }
    cases.push_back(sy);
  }
  {
    for (const auto& sy : cases) {
      std::string out;
      RangeEncoder enc(out);
      BitModel m[2];
      for (const Symbol& x : sy)
        x.model >= 0 ? enc.encode_bit(m[x.model], x.value) : enc.encode_raw(x.value, -x.model);
      enc.finish();
      auto same = [&](std::string_view bytes) {
        try {
          RangeDecoder dec(bytes, 0, "test stream");
          BitModel d[2];
          for (const Symbol& x : sy)
            if ((x.model >= 0 ? dec.decode_bit(d[x.model]) : dec.decode_raw(-x.model)) != x.value)
              return false;
          dec.finish();
          return true;
        } catch (const Error&) {
          return false;
        }
      };
      ASSERT_TRUE(same(out));
      for (std::size_t i = 0; i < out.size(); ++i)
        for (int b = 0; b < 256; ++b) {
          std::string bad = out;
          if (bad[i] == static_cast<char>(b)) continue;
          bad[i] = static_cast<char>(b);
          EXPECT_FALSE(same(bad)) << "byte " << i << " = " << b;
        }
      for (int b = 0; b < 256; ++b) EXPECT_FALSE(same(out + static_cast<char>(b))) << "appended " << b;
      if (!out.empty()) {
        EXPECT_FALSE(same(std::string_view(out).substr(0, out.size() - 1)));
      }
    }
  }
}

// Compact ends: no leading zero and 3 or 4 zero bytes left out of the flush (4 or 5 bytes less than
// LZMA's ends), for any number of symbols: the empty stream is empty. The decoder reads the left-out
// zeros back, accepts only the encoder's own ending for the symbols it decoded, and refuses a stream
// that needs more than 4 zeros.
TEST(Entropy, CompactEndsAreShortAndStrict) {
  std::mt19937 rng(13);
  for (int count : {0, 1, 2, 5, 17, 100, 1000, 5000}) {
    SCOPED_TRACE(count);
    std::vector<unsigned> bits(static_cast<std::size_t>(count));
    std::vector<std::uint32_t> raw(bits.size());
    for (std::size_t i = 0; i < bits.size(); ++i) bits[i] = rng() % 4 == 0, raw[i] = rng() & 0x3FF;
    auto code = [&] {
      std::string out;
      RangeEncoder enc(out);
      BitModel m;
      for (std::size_t i = 0; i < bits.size(); ++i) {
        enc.encode_bit(m, bits[i]);
        if (i % 7 == 0) enc.encode_raw(raw[i], 10);
      }
      enc.finish();
      return out;
    };
    auto run = [&](std::string_view s) {
      RangeDecoder dec(s, 0, "test stream");
      BitModel m;
      for (std::size_t i = 0; i < bits.size(); ++i) {
        if (dec.decode_bit(m) != bits[i]) return false;
        if (i % 7 == 0 && dec.decode_raw(10) != raw[i]) return false;
      }
      dec.finish();
      return true;
    };
    const std::string compact = code();
    if (count == 0) {
      EXPECT_TRUE(compact.empty());
    } else {  // the last byte written is never a zero: such zeros are left out
      EXPECT_NE(compact.back(), '\0');
    }
    EXPECT_TRUE(run(compact));
    // A zero appended, the last byte cut or changed: not these symbols, or refused.
    auto same = [&](std::string_view s) {
      try {
        return run(s);
      } catch (const Error&) {
        return false;
      }
    };
    EXPECT_THROW(run(compact + std::string(1, '\0')), Error);
    EXPECT_FALSE(same(compact + std::string(1, '\x5A')));
    if (!compact.empty()) {
      EXPECT_FALSE(same(compact.substr(0, compact.size() - 1)));
      std::string changed = compact;
      changed.back() = static_cast<char>(changed.back() ^ 1);
      EXPECT_FALSE(same(changed));
    }
  }
  // A stream whose symbols need more than the 4 zeros: ends too early.
  std::string out;
  RangeEncoder enc(out);
  enc.encode_raw(0x2A5u, 10);
  enc.encode_raw(0x3FFFFFu, 22);
  enc.finish();
  RangeDecoder dec(std::string_view(out).substr(0, out.size() - 2), 0, "test stream");
  EXPECT_THROW(
      {
        dec.decode_raw(10);
        dec.decode_raw(22);
        dec.decode_raw(32);
        dec.decode_raw(32);
      },
      Error);
}

}  // namespace
}  // namespace qsp
