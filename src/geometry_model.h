// The geometry section's residual model (format-spec/geometry_section.md, "Residual coding", "Residual
// model"): a residual's zigzag value u as its bit length (a 6-decision binary tree) and then the bits
// below its leading one (the first two modelled, the rest raw), in contexts of the vertex's kind and
// magnitude class. Each length decision mixes two models by how much each has seen (mixed decisions),
// or, with the logistic mixing tool, four models in the logistic domain with learnt weights (logistic
// decisions), and the length trees start from a prior.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "entropy.h"
#include "geometry_hood.h"

namespace qsp {

inline constexpr int kClasses = 24;      // magnitude classes
inline constexpr int kModelledBits = 2;  // mantissa bits with their own contexts

// ---- Mixed decisions: two models' probabilities averaged, each weighted by how much it has seen
// (min(seen, 30) + 1): a young specific model defers to the general one, a trained one to itself. A
// specific model that has seen kMixUntil bits codes alone (and the general one no longer learns from
// it): mixing then gains nothing, and a large mesh decodes almost as fast as with one model.

inline constexpr unsigned kMixUntil = 64;
// So a model coding alone is mature (learn_mature, without testing its count again).
static_assert(kMixUntil == kMature);

// ceil(2^32 / d) for d = wa + wb in 2..62: (n * it) >> 32 is n / d for every n below 65536 * 62 (checked
// exhaustively), a multiplication where the division was on the decoder's critical path.
inline constexpr std::array<std::uint32_t, 63> kMixReciprocal = [] {
  std::array<std::uint32_t, 63> t{};
  for (std::uint64_t d = 2; d < 63; ++d)
    t[d] = static_cast<std::uint32_t>(((std::uint64_t{1} << 32) + d - 1) / d);
  return t;
}();

inline std::uint32_t mixed_p0(const BitModel& a, const BitModel& b) {
  const std::uint32_t wa = std::min<std::uint32_t>(a.seen, 30) + 1,
                      wb = std::min<std::uint32_t>(b.seen, 30) + 1;
  const std::uint64_t n = a.p0() * wa + b.p0() * wb;  // / (wa + wb)
  return static_cast<std::uint32_t>((n * kMixReciprocal[wa + wb]) >> 32);
}
inline void encode_mixed(RangeEncoder& rc, BitModel& a, BitModel& b, unsigned bit) {
  if (a.seen >= kMixUntil) {
    rc.encode_p0(a.p0(), bit);
    return learn_mature(a, bit);
  }
  rc.encode_p0(mixed_p0(a, b), bit);
  learn(a, bit);
  learn(b, bit);
}
inline unsigned decode_mixed(RangeDecoder& rc, BitModel& a, BitModel& b) {
  if (a.seen >= kMixUntil) {
    const unsigned bit = rc.decode_p0(a.p0());
    learn_mature<Learn::kMask>(a, bit);
    return bit;
  }
  const unsigned bit = rc.decode_p0(mixed_p0(a, b));
  learn<Learn::kMask>(a, bit);
  learn<Learn::kMask>(b, bit);
  return bit;
}

// ---- Logistic decisions, after lpaq1: a probability of a 1 in 12 bits, its logit `stretch` in
// [-2047, 2047] (8 fractional bits), and `squash` back by interpolation in a 33-entry table. All
// integer, so encoder and decoder agree bit for bit.

inline constexpr std::array<int, 33> kSquash = {
    1,    2,    3,    6,    10,   16,   27,   45,   73,   120,  194,  310,  488,  747,  1101, 1546, 2047,
    2549, 2994, 3348, 3607, 3785, 3901, 3975, 4024, 4050, 4068, 4079, 4085, 4089, 4092, 4093, 4094};
constexpr int squash(int d) {  // d in [-2047, 2047]
  const int w = d & 127;
  const auto i = static_cast<std::size_t>((d >> 7) + 16);
  return (kSquash[i] * (128 - w) + kSquash[i + 1] * w + 64) >> 7;
}
// stretch[p]: the smallest d in [-2047, 2047] with squash(d) >= p, else 2047.
inline constexpr std::array<std::int16_t, 4096> kStretch = [] {
  std::array<std::int16_t, 4096> t{};
  int p = 0;
  for (int d = -2047; d <= 2047; ++d)
    for (const int v = squash(d); p <= v; ++p) t[static_cast<std::size_t>(p)] = static_cast<std::int16_t>(d);
  for (; p < 4096; ++p) t[static_cast<std::size_t>(p)] = 2047;
  return t;
}();

// The two as the coder uses them, one lookup each: squash(d) by d + 2047, and the stretch of a model's
// probability of a 1, clamp(4096 - (p0 >> 4), 1, 4095), by p0 >> 4 (interpolating and clamping were a
// fifth of a logistic decision).
inline constexpr std::array<std::int16_t, 4095> kSquashed = [] {
  std::array<std::int16_t, 4095> t{};
  for (int d = -2047; d <= 2047; ++d)
    t[static_cast<std::size_t>(d + 2047)] = static_cast<std::int16_t>(squash(d));
  return t;
}();
inline constexpr std::array<std::int16_t, 4096> kStretchOfP0 = [] {
  std::array<std::int16_t, 4096> t{};
  for (int q = 0; q < 4096; ++q)
    t[static_cast<std::size_t>(q)] = kStretch[static_cast<std::size_t>(std::clamp(4096 - q, 1, 4095))];
  return t;
}();

// One weight set: four models' weights and the bias's, 16.16 fixed point.
inline constexpr int kMixInputs = 5;
inline constexpr std::int32_t kMaxWeight = std::int32_t{1} << 22;  // a hostile stream cannot overflow them
struct MixWeights {
  std::array<std::int32_t, kMixInputs> w = {6 << 12, 3 << 12, 3 << 12, 3 << 12, 0};
};

// Codes (RangeEncoder) or decodes (RangeDecoder) one bit with four models mixed by weight set `mw`; all
// four models learn it, and so do the weights, at kRate (the geometry section's 6; the coded comments
// section's text model learns at 10).
template <int kRate = 6, typename Coder>
void code_logistic(Coder& rc, unsigned& bit, const std::array<BitModel*, 4>& models, MixWeights& mw) {
  std::array<int, kMixInputs> st{};
  std::int64_t dot = 0;
  for (std::size_t k = 0; k < 4; ++k) st[k] = kStretchOfP0[models[k]->p0() >> 4];
  st[4] = 256;
  for (std::size_t k = 0; k < kMixInputs; ++k) dot += std::int64_t{mw.w[k]} * st[k];
  const int p1 = kSquashed[static_cast<std::size_t>(std::clamp<std::int64_t>(dot >> 16, -2047, 2047) + 2047)];
  // Clamped to the adaptive models' own range, so no decision costs less than log2(65536 / 65465) bits
  // and the decoder's bound on vertices per geometry byte (codec.cpp) holds.
  const std::uint32_t p0 = std::clamp<std::uint32_t>(static_cast<std::uint32_t>(4096 - p1) << 4, 71, 65465);
  if constexpr (std::is_same_v<Coder, RangeEncoder>) {
    rc.encode_p0(p0, bit);
  } else {
    bit = rc.decode_p0(p0);
  }
  const int err = ((static_cast<int>(bit) << 12) - p1) * kRate;
  for (std::size_t k = 0; k < kMixInputs; ++k)
    mw.w[k] = std::clamp(mw.w[k] + ((st[k] * err) >> 14), -kMaxWeight, kMaxWeight);
  for (BitModel* m : models) learn<Learn::kSelect>(*m, bit);
}

// A residual's contexts.
struct ResidualContext {
  int kind = 0;           // context kind, 0..8
  int cls = 0;            // magnitude class, 0..23
  int max_len = 0;        // the axis's largest valid length: no decision for lengths beyond it
  int axis = 0;           // logistic mixing: the axis,
  int neighbour_cls = 0;  //   the neighbour class (the neighbours' magnitudes alone),
  int previous = 0;       //   the length of the vertex's previous axis (at most 23)
};

// The three axes share models: on small meshes, learning three times faster beats separate ones.
class ResidualModel {
 public:
  // `logistic`: the logistic mixing tool (its tables, weights and length prior).
  explicit ResidualModel(bool logistic);

  // Inlined into code_symbols (geometry_sink.cpp), which builds the context from a symbol's bytes.
  template <bool kLogistic>
  [[gnu::always_inline]] inline void encode(RangeEncoder& rc, std::uint64_t u, const ResidualContext& c);
  // Inlined into the decoder's loop: a call per coordinate cost 3% of a decode.
  template <bool kLogistic>
  [[gnu::always_inline]] inline std::uint64_t decode(RangeDecoder& rc, const ResidualContext& c);
  bool logistic() const { return logistic_; }

  // Trailing decimal zeros t (0..12) as a 4-decision tree, most significant first, by the digit count
  // of the prediction (0..15).
  void encode_zeros(RangeEncoder& rc, int t, int digits);
  int decode_zeros(RangeDecoder& rc, int digits);  // -1 for a t above 12

  // Value repeats: the decision (by context kind, and how the vertex's previous axis went: 0 axis x,
  // 1 residual, 2 repeat) and the rank.
  BitModel& repeat(int kind, int previous) {
    return repeat_[static_cast<std::size_t>(kind) * 3 + static_cast<std::size_t>(previous)];
  }
  IntModel rank;

 private:
  BitModel* length_tree(int kind, int cls) {
    return &length_[(static_cast<std::size_t>(kind) * kClasses + static_cast<std::size_t>(cls)) * 64];
  }
  BitModel* mantissa_tree(int len) { return &mantissa_[static_cast<std::size_t>(len) * 4]; }
  template <typename Coder>
  void code_length_bit(Coder& rc, unsigned& bit, const ResidualContext& c, int node);
  template <typename Coder>
  void code_mantissa_bit(Coder& rc, unsigned& bit, int len, const ResidualContext& c, int node);
  void set_prior();

  bool logistic_;
  std::vector<BitModel> length_;    // [kind][class][node 1..63]
  std::vector<BitModel> general_;   // [kind][node 1..63]: mixed into every class's tree
  std::vector<BitModel> mantissa_;  // [L][node 1..3]
  std::vector<BitModel> zeros_;     // [digit count of |prediction| 0..15][node 1..15]
  std::vector<BitModel> repeat_;    // [kind][previous axis]
  // Logistic mixing: each length decision mixes the class's model, the kind's, and models by (kind,
  // axis, neighbours' class) and by (kind, axis, length of the vertex's previous axis); each of the two
  // modelled mantissa bits mixes the length's model and models by (length, class), (length, kind) and
  // (length, axis, neighbours' class). Weight sets by decision and whether the context kind is 3.
  std::vector<BitModel> by_class_;            // [kind][axis][class][node 1..63]
  std::vector<BitModel> by_previous_;         // [kind][axis][previous length][node 1..63]
  std::vector<MixWeights> length_weights_;    // [blended][node 1..63]
  std::vector<BitModel> mantissa_bucket_;     // [L][class][node 1..3]
  std::vector<BitModel> mantissa_kind_;       // [L][kind][node 1..3]
  std::vector<BitModel> mantissa_class_;      // [L][axis][neighbour class][node 1..3]
  std::vector<MixWeights> mantissa_weights_;  // [blended][node 1..3]
};

template <typename Coder>
void ResidualModel::code_length_bit(Coder& rc, unsigned& bit, const ResidualContext& c, int node) {
  const auto n = static_cast<std::size_t>(node);
  const std::size_t k = static_cast<std::size_t>(c.kind) * 3 + static_cast<std::size_t>(c.axis);
  code_logistic(rc, bit,
                {&length_tree(c.kind, c.cls)[n], &general_[static_cast<std::size_t>(c.kind) * 64 + n],
                 &by_class_[(k * kClasses + static_cast<std::size_t>(c.neighbour_cls)) * 64 + n],
                 &by_previous_[(k * kClasses + static_cast<std::size_t>(c.previous)) * 64 + n]},
                length_weights_[(c.kind == kBlendedContext ? 64 : 0) + n]);
}

template <typename Coder>
void ResidualModel::code_mantissa_bit(Coder& rc, unsigned& bit, int len, const ResidualContext& c, int node) {
  const auto n = static_cast<std::size_t>(node), l = static_cast<std::size_t>(len);
  code_logistic(
      rc, bit,
      {&mantissa_tree(len)[n], &mantissa_bucket_[(l * kClasses + static_cast<std::size_t>(c.cls)) * 4 + n],
       &mantissa_kind_[(l * kContextKinds + static_cast<std::size_t>(c.kind)) * 4 + n],
       &mantissa_class_[((l * 3 + static_cast<std::size_t>(c.axis)) * kClasses +
                         static_cast<std::size_t>(c.neighbour_cls)) *
                            4 +
                        n]},
      mantissa_weights_[(c.kind == kBlendedContext ? 4 : 0) + n]);
}

// Length decision i (of weight 2^i) is left out when a 1 could only lead to lengths above max_len,
// given the decisions above it (`high`): at 14 bits, the top two never vary.
constexpr bool excluded(int high, int i, int max_len) { return (high | (1 << i)) > max_len; }

// By max_len (at most 42), the length tree's nodes whose decision is coded (bit `node`, 1..63), and
// the top level that may have one: a table lookup and a bit test, where testing each level's
// exclusion was a quarter of coding a residual.
inline constexpr std::array<std::uint64_t, 64> kCodedNodes = [] {
  std::array<std::uint64_t, 64> t{};
  for (int max_len = 0; max_len < 64; ++max_len) {
    for (int node = 1; node < 64; ++node) {
      const int i = 6 - std::bit_width(static_cast<unsigned>(node));  // the node's level
      if (!excluded((node << (i + 1)) - 64, i, max_len))
        t[static_cast<std::size_t>(max_len)] |= std::uint64_t{1} << node;
    }
  }
  return t;
}();
inline bool coded_node(std::uint64_t coded, int node) { return (coded >> node) & 1u; }
// Levels above it are never coded: their 1 alone passes max_len.
inline int top_level(int max_len) { return std::bit_width(static_cast<unsigned>(max_len)) - 1; }

template <bool kLogistic>
inline void ResidualModel::encode(RangeEncoder& rc, std::uint64_t u, const ResidualContext& c) {
  const int len = std::bit_width(u);
  BitModel* tree = length_tree(c.kind, c.cls);
  BitModel* kind_tree = &general_[static_cast<std::size_t>(c.kind) * 64];
  const std::uint64_t coded = kCodedNodes[static_cast<std::size_t>(c.max_len)];
  for (int i = top_level(c.max_len); i >= 0; --i) {
    const int node = (64 + len) >> (i + 1);  // 1, then the bits of len above bit i
    if (!coded_node(coded, node)) continue;  // b is 0: len <= max_len
    unsigned b = (len >> i) & 1;
    if constexpr (kLogistic) {
      code_length_bit(rc, b, c, node);
    } else {
      encode_mixed(rc, tree[node], kind_tree[node], b);
    }
  }
  if (len <= 1) return;
  BitModel* m = mantissa_tree(len);
  const int rest = len - 1, modelled = std::min(rest, kModelledBits);
  for (int i = 0, node = 1; i < modelled; ++i) {
    unsigned b = (u >> (rest - 1 - i)) & 1;
    if constexpr (kLogistic) {
      code_mantissa_bit(rc, b, len, c, node);
    } else {
      rc.encode_bit(m[node], b);
    }
    node = 2 * node + static_cast<int>(b);
  }
  const int raw = rest - modelled;  // up to 40: two calls of at most 20 bits
  if (raw > 20)
    rc.encode_raw(static_cast<std::uint32_t>((u >> 20) & ((1u << (raw - 20)) - 1)),
                  static_cast<unsigned>(raw - 20));
  rc.encode_raw(static_cast<std::uint32_t>(u & ((1u << std::min(raw, 20)) - 1)),
                static_cast<unsigned>(std::min(raw, 20)));
}

template <bool kLogistic>
inline std::uint64_t ResidualModel::decode(RangeDecoder& rc, const ResidualContext& c) {
  BitModel* tree = length_tree(c.kind, c.cls);
  BitModel* kind_tree = &general_[static_cast<std::size_t>(c.kind) * 64];
  const std::uint64_t coded = kCodedNodes[static_cast<std::size_t>(c.max_len)];
  const int top = top_level(c.max_len);
  int node = 64 >> (top + 1);  // the levels above top decided 0
  for (int i = top; i >= 0; --i) {
    if (!coded_node(coded, node)) {
      node = 2 * node;
      continue;
    }
    if constexpr (kLogistic) {
      unsigned b = 0;
      code_length_bit(rc, b, c, node);
      node = 2 * node + static_cast<int>(b);
    } else {
      node = 2 * node + static_cast<int>(decode_mixed(rc, tree[node], kind_tree[node]));
    }
  }
  const int len = node - 64;  // at most max_len: every decision that could pass it was left out
  if (len <= 1) return static_cast<std::uint64_t>(len);
  BitModel* m = mantissa_tree(len);
  const int rest = len - 1, modelled = std::min(rest, kModelledBits);
  std::uint64_t u = 1;
  for (int i = 0, n = 1; i < modelled; ++i) {
    unsigned b = 0;
    if constexpr (kLogistic) {
      code_mantissa_bit(rc, b, len, c, n);
    } else {
      b = rc.decode_bit(m[n]);
    }
    n = 2 * n + static_cast<int>(b);
    u = (u << 1) | b;
  }
  const int raw = rest - modelled;
  if (raw > 20) u = (u << (raw - 20)) | rc.decode_raw(static_cast<unsigned>(raw - 20));
  return (u << std::min(raw, 20)) | rc.decode_raw(static_cast<unsigned>(std::min(raw, 20)));
}

}  // namespace qsp
