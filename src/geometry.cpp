// Geometry coding: per-vertex prediction from grid neighbours, residuals through an adaptive binary
// range coder. The byte layout is specified in format-spec/qsp_format.md, "Geometry section"; keep
// them in sync.
//
// Determinism: integer axes (decimal grids, quantized) predict with integer arithmetic only. Float
// axes predict with additions in binary64 and one rounding to binary32, and dequantization multiplies
// by a step whose product is exact. So FMA contraction cannot change a result, and the decoder
// recomputes the encoder's predictions bit for bit on any IEEE-754 machine.
#include "qsp/geometry.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <system_error>
#include <thread>
#include <type_traits>

#include "qsp/entropy.h"
#include "qsp/error.h"

namespace qsp {
namespace {

[[noreturn]] void fail(const char* what) {
  throw Error(ErrorCode::kFormat, std::string("geometry: ") + what);
}

// ---------------------------------------------------------------------------------------------
// Bytes

void put_u8(std::string& out, std::uint8_t v) { out.push_back(static_cast<char>(v)); }

void put_varint(std::string& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>((v & 0x7F) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}

void put_le(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  std::size_t left() const { return bytes_.size() - pos_; }
  std::size_t pos() const { return pos_; }

  std::uint8_t u8(const char* what) {
    if (left() < 1) fail(what);
    return static_cast<std::uint8_t>(bytes_[pos_++]);
  }
  std::uint64_t le(int n, const char* what) {
    if (left() < static_cast<std::size_t>(n)) fail(what);
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t{static_cast<std::uint8_t>(bytes_[pos_++])} << (8 * i);
    return v;
  }
  // LEB128, at most 64 bits, minimal length (a unique encoding keeps corruption detectable).
  std::uint64_t varint(const char* what) {
    std::uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      const std::uint8_t b = u8(what);
      if (shift == 63 && b > 1) fail(what);
      v |= std::uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) {
        if (b == 0 && shift > 0) fail(what);
        return v;
      }
    }
  }
  std::string_view take(std::size_t n, const char* what) {
    if (left() < n) fail(what);
    std::string_view s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Residual model: zigzag value u, coded as its bit length L (6-bit binary tree) and then the bits
// below the leading one (the first two with adaptive contexts, the rest raw).

constexpr int kKinds =
    9;  // context kinds: Kind 0..4, kWest/kLinear with a far end (5, 6), kOpposite (7), kCorners (8)
constexpr int kBuckets = 24;           // neighbourhood magnitude classes
constexpr int kModelledBits = 2;       // mantissa bits with their own contexts
constexpr int kMaxTrailingZeros = 12;  // decimal integers: 10^12 < 2^40 < 10^13
constexpr int kBlendedKind = 3;        // the context kind of kParallelogram, the blended vertices

// Logistic decisions (revision 6; format spec, "Entropy coding"), after lpaq1: a probability of a 1 in
// 12 bits, its logit `stretch` in [-2047, 2047] (8 fractional bits), and `squash` back by interpolation
// in a 33-entry table. All integer, so encoder and decoder agree bit for bit.
constexpr std::array<int, 33> kSquash = {1,    2,    3,    6,    10,   16,   27,   45,   73,   120,  194,
                                         310,  488,  747,  1101, 1546, 2047, 2549, 2994, 3348, 3607, 3785,
                                         3901, 3975, 4024, 4050, 4068, 4079, 4085, 4089, 4092, 4093, 4094};
constexpr int squash(int d) {  // d in [-2047, 2047]
  const int w = d & 127;
  const auto i = static_cast<std::size_t>((d >> 7) + 16);
  return (kSquash[i] * (128 - w) + kSquash[i + 1] * w + 64) >> 7;
}
// stretch[p]: the smallest d in [-2047, 2047] with squash(d) >= p, else 2047.
constexpr std::array<std::int16_t, 4096> kStretch = [] {
  std::array<std::int16_t, 4096> t{};
  int p = 0;
  for (int d = -2047; d <= 2047; ++d)
    for (const int v = squash(d); p <= v; ++p) t[static_cast<std::size_t>(p)] = static_cast<std::int16_t>(d);
  for (; p < 4096; ++p) t[static_cast<std::size_t>(p)] = 2047;
  return t;
}();

// One weight set: four models' weights and the bias's, 16.16 fixed point.
constexpr int kMixInputs = 5;
constexpr std::int32_t kMaxWeight = std::int32_t{1} << 22;  // a hostile stream cannot overflow them
struct MixWeights {
  std::array<std::int32_t, kMixInputs> w = {6 << 12, 3 << 12, 3 << 12, 3 << 12, 0};
};

// Codes (RangeEncoder) or decodes (RangeDecoder) one bit with four models mixed by weight set `mw`; all
// four models learn it, and so do the weights.
template <typename Coder>
void code_mixed(Coder& rc, unsigned& bit, const std::array<BitModel*, 4>& models, MixWeights& mw) {
  std::array<int, kMixInputs> st{};
  std::int64_t dot = 0;
  for (int k = 0; k < 4; ++k) {
    const int p1 =
        std::clamp(4096 - static_cast<int>(models[static_cast<std::size_t>(k)]->p0() >> 4), 1, 4095);
    st[static_cast<std::size_t>(k)] = kStretch[static_cast<std::size_t>(p1)];
  }
  st[4] = 256;
  for (std::size_t k = 0; k < kMixInputs; ++k) dot += std::int64_t{mw.w[k]} * st[k];
  const int p1 = squash(static_cast<int>(std::clamp<std::int64_t>(dot >> 16, -2047, 2047)));
  // Clamped to the adaptive models' own range, so no decision costs less than log2(65536 / 65465) bits
  // and the decoder's bound on vertices per geometry byte (codec.cpp) holds in every revision.
  const std::uint32_t p0 = std::clamp<std::uint32_t>(static_cast<std::uint32_t>(4096 - p1) << 4, 71, 65465);
  if constexpr (std::is_same_v<Coder, RangeEncoder>) {
    rc.encode_p0(p0, bit);
  } else {
    bit = rc.decode_p0(p0);
  }
  const int err = ((static_cast<int>(bit) << 12) - p1) * 6;
  for (std::size_t k = 0; k < kMixInputs; ++k)
    mw.w[k] = std::clamp(mw.w[k] + ((st[k] * err) >> 14), -kMaxWeight, kMaxWeight);
  for (BitModel* m : models) learn(*m, bit);
}

// The mixer's contexts of one residual beyond its kind and bucket (revision 6).
struct Extra {
  int axis = 0, cls = 0, previous = 0;  // previous: the length of the vertex's previous axis, at most 23
};

// The three axes share contexts: on small meshes, learning three times faster beats separate models.
struct ResidualModel {
  std::vector<BitModel> length;    // [kind][bucket][node 1..63]
  std::vector<BitModel> general;   // [kind][node 1..63]: revision 3 mixes it into every bucket's tree
  bool mixed = false;              // revisions 3-6 (revision 6 mixes logistically)
  bool exclude = false;            // revisions 4-6: no decision for lengths above the axis's maximum
  std::vector<BitModel> mantissa;  // [L][node 1..3]
  std::vector<BitModel> zeros;     // [digit count of |prediction| 0..15][node 1..15]
  std::vector<BitModel> repeat;    // [kind][previous axis of the vertex: 0 none, 1 coded, 2 repeat]
  IntModel rank;                   // a repeat's rank
  // Revision 6: each length decision mixes the bucket's model, the kind's, and models by (kind, axis,
  // neighbours' class) and by (kind, axis, length of the vertex's previous axis); each of the two
  // modelled mantissa bits mixes the length's model and models by (length, bucket), (length, kind) and
  // (length, axis, class). Weight sets by decision and whether the context kind is 3 (a full cell).
  bool logistic = false;
  std::vector<BitModel> by_class;            // [kind][axis][class][node 1..63]
  std::vector<BitModel> by_previous;         // [kind][axis][previous length, at most 23][node 1..63]
  std::vector<MixWeights> length_weights;    // [blended][node 1..63]
  std::vector<BitModel> mantissa_bucket;     // [L][bucket][node 1..3]
  std::vector<BitModel> mantissa_kind;       // [L][kind][node 1..3]
  std::vector<BitModel> mantissa_class;      // [L][axis][class][node 1..3]
  std::vector<MixWeights> mantissa_weights;  // [blended][node 1..3]
  void set_logistic() {
    logistic = true;
    by_class.resize(std::size_t{kKinds} * 3 * kBuckets * 64);
    by_previous.resize(std::size_t{kKinds} * 3 * kBuckets * 64);
    length_weights.resize(2 * 64);
    mantissa_bucket.resize(std::size_t{64} * kBuckets * 4);
    mantissa_kind.resize(std::size_t{64} * kKinds * 4);
    mantissa_class.resize(std::size_t{64} * 3 * kBuckets * 4);
    mantissa_weights.resize(2 * 4);
  }
  template <typename Coder>
  void code_length_bit(Coder& rc, unsigned& bit, int kind, int bucket, const Extra& e, int node) {
    const std::size_t n = static_cast<std::size_t>(node);
    const std::size_t k = static_cast<std::size_t>(kind) * 3 + static_cast<std::size_t>(e.axis);
    code_mixed(rc, bit,
               {&length_tree(kind, bucket)[n], &general[static_cast<std::size_t>(kind) * 64 + n],
                &by_class[(k * kBuckets + static_cast<std::size_t>(e.cls)) * 64 + n],
                &by_previous[(k * kBuckets + static_cast<std::size_t>(e.previous)) * 64 + n]},
               length_weights[(kind == kBlendedKind ? 64 : 0) + n]);
  }
  template <typename Coder>
  void code_mantissa_bit(Coder& rc, unsigned& bit, int len, int kind, int bucket, const Extra& e, int node) {
    const std::size_t n = static_cast<std::size_t>(node), l = static_cast<std::size_t>(len);
    code_mixed(
        rc, bit,
        {&mantissa_tree(len)[n], &mantissa_bucket[(l * kBuckets + static_cast<std::size_t>(bucket)) * 4 + n],
         &mantissa_kind[(l * kKinds + static_cast<std::size_t>(kind)) * 4 + n],
         &mantissa_class
             [((l * 3 + static_cast<std::size_t>(e.axis)) * kBuckets + static_cast<std::size_t>(e.cls)) * 4 +
              n]},
        mantissa_weights[(kind == kBlendedKind ? 4 : 0) + n]);
  }

  ResidualModel(bool mix, bool excluding)
      : length(kKinds * kBuckets * 64),
        general(mix ? kKinds * 64 : 0),
        mixed(mix),
        exclude(excluding),
        mantissa(64 * 4),
        zeros(16 * 16),
        repeat(kKinds * 3) {}

  // Trailing decimal zeros t (0..12) as a 4-bit tree, most significant bit first.
  void encode_zeros(RangeEncoder& rc, int t, int digits) {
    BitModel* tree = &zeros[static_cast<std::size_t>(digits) * 16];
    for (int i = 3, node = 1; i >= 0; --i) {
      const unsigned b = (t >> i) & 1;
      rc.encode_bit(tree[node], b);
      node = 2 * node + static_cast<int>(b);
    }
  }
  int decode_zeros(RangeDecoder& rc, int digits) {
    BitModel* tree = &zeros[static_cast<std::size_t>(digits) * 16];
    int node = 1;
    for (int i = 0; i < 4; ++i) node = 2 * node + static_cast<int>(rc.decode_bit(tree[node]));
    if (node - 16 > kMaxTrailingZeros) fail("too many trailing zeros");
    return node - 16;
  }

  // Revision 6: each bucket's length tree starts from a distribution centred on the bucket, as if it
  // had seen 3 bits: a length d below the bucket weighs 2^-d, d above it 2^-3d (residuals spread
  // downwards from the typical length, rarely upwards). Format spec, "Length prior".
  void set_prior() {
    static const std::vector<std::uint16_t> prior = [] {  // [bucket][node 1..63]
      std::vector<std::uint16_t> p(std::size_t{kBuckets} * 64);
      for (int b = 0; b < kBuckets; ++b) {
        std::array<std::uint64_t, 128> weight{};  // [node]: leaf 64 + L, an inner node the sum below it
        for (int len = 0; len < 64; ++len)
          weight[static_cast<std::size_t>(64 + len)] =
              std::uint64_t{1} << (40 - std::min(40, len <= b ? b - len : 3 * (len - b)));
        for (std::size_t node = 63; node >= 1; --node) weight[node] = weight[2 * node] + weight[2 * node + 1];
        for (std::size_t node = 1; node < 64; ++node) {
          p[static_cast<std::size_t>(b) * 64 + node] = static_cast<std::uint16_t>(
              std::clamp<std::uint64_t>((weight[2 * node] << 16) / weight[node], 1024, 64512));
        }
      }
      return p;
    }();
    for (int kind = 0; kind < kKinds; ++kind) {
      for (int b = 0; b < kBuckets; ++b) {
        BitModel* tree = length_tree(kind, b);
        for (std::size_t node = 1; node < 64; ++node) {
          const std::uint16_t p = prior[static_cast<std::size_t>(b) * 64 + node];
          tree[node] = BitModel{p, p, 3};
        }
      }
    }
  }

  BitModel* length_tree(int kind, int bucket) {
    return &length[(static_cast<std::size_t>(kind) * kBuckets + bucket) * 64];
  }
  BitModel* mantissa_tree(int len) { return &mantissa[static_cast<std::size_t>(len) * 4]; }

  // Length decision i (of weight 2^i) is left out in revisions 4-6 when a 1 could only lead to lengths
  // above max_len, given the decisions above it (`high`): at 14 bits, the top two never vary.
  bool forced(int high, int i, int max_len) const { return exclude && (high | (1 << i)) > max_len; }

  // Revision 6's logistic decisions are a template argument, so that revisions 1-5 decode as fast as
  // they did before it (the branch in the loop cost cc2's decoder 3% of its instructions).
  // `e`: revision 6's contexts (unread, and may be null, in revisions 1-5).
  void encode(RangeEncoder& rc, std::uint64_t u, int kind, int bucket, int max_len, const Extra* e) {
    logistic ? encode<true>(rc, u, kind, bucket, max_len, e) : encode<false>(rc, u, kind, bucket, max_len, e);
  }
  std::uint64_t decode(RangeDecoder& rc, int kind, int bucket, int max_len, const Extra* e) {
    return logistic ? decode<true>(rc, kind, bucket, max_len, e)
                    : decode<false>(rc, kind, bucket, max_len, e);
  }

  template <bool kLogistic>
  void encode(RangeEncoder& rc, std::uint64_t u, int kind, int bucket, int max_len, const Extra* e) {
    const int len = std::bit_width(u);
    BitModel* tree = length_tree(kind, bucket);
    BitModel* kind_tree = mixed ? &general[static_cast<std::size_t>(kind) * 64] : nullptr;
    for (int i = 5, node = 1; i >= 0; --i) {
      unsigned b = (len >> i) & 1;
      if (forced(len & ~((2 << i) - 1), i, max_len)) {
        node = 2 * node;  // b is 0: len <= max_len
        continue;
      }
      if constexpr (kLogistic) {
        code_length_bit(rc, b, kind, bucket, *e, node);
      } else if (mixed) {
        rc.encode_bit(tree[node], kind_tree[node], b);
      } else {
        rc.encode_bit(tree[node], b);
      }
      node = 2 * node + static_cast<int>(b);
    }
    if (len <= 1) return;
    BitModel* m = mantissa_tree(len);
    const int rest = len - 1, modelled = std::min(rest, kModelledBits);
    for (int i = 0, node = 1; i < modelled; ++i) {
      unsigned b = (u >> (rest - 1 - i)) & 1;
      if constexpr (kLogistic) {
        code_mantissa_bit(rc, b, len, kind, bucket, *e, node);
      } else {
        rc.encode_bit(m[node], b);
      }
      node = 2 * node + static_cast<int>(b);
    }
    const int raw = rest - modelled;  // up to 40: two calls of at most 20 bits
    if (raw > 20) rc.encode_raw(static_cast<std::uint32_t>((u >> 20) & ((1u << (raw - 20)) - 1)), raw - 20);
    rc.encode_raw(static_cast<std::uint32_t>(u & ((1u << std::min(raw, 20)) - 1)), std::min(raw, 20));
  }

  template <bool kLogistic>
  std::uint64_t decode(RangeDecoder& rc, int kind, int bucket, int max_len, const Extra* e) {
    BitModel* tree = length_tree(kind, bucket);
    BitModel* kind_tree = mixed ? &general[static_cast<std::size_t>(kind) * 64] : nullptr;
    int node = 1;
    for (int i = 5; i >= 0; --i) {
      if (forced((node << (i + 1)) - 64, i, max_len)) {
        node = 2 * node;
        continue;
      }
      if constexpr (kLogistic) {
        unsigned b = 0;
        code_length_bit(rc, b, kind, bucket, *e, node);
        node = 2 * node + static_cast<int>(b);
        continue;
      }
      node = 2 * node +
             static_cast<int>(mixed ? rc.decode_bit(tree[node], kind_tree[node]) : rc.decode_bit(tree[node]));
    }
    const int len = node - 64;
    if (len > max_len) fail("residual longer than its mode allows");
    if (len <= 1) return static_cast<std::uint64_t>(len);
    BitModel* m = mantissa_tree(len);
    const int rest = len - 1, modelled = std::min(rest, kModelledBits);
    std::uint64_t u = 1;
    for (int i = 0, n = 1; i < modelled; ++i) {
      unsigned b = 0;
      if constexpr (kLogistic) {
        code_mantissa_bit(rc, b, len, kind, bucket, *e, n);
      } else {
        b = rc.decode_bit(m[n]);
      }
      n = 2 * n + static_cast<int>(b);
      u = (u << 1) | b;
    }
    const int raw = rest - modelled;
    if (raw > 20) u = (u << (raw - 20)) | rc.decode_raw(raw - 20);
    return (u << std::min(raw, 20)) | rc.decode_raw(std::min(raw, 20));
  }
};

std::uint64_t zigzag64(std::int64_t r) {
  return (static_cast<std::uint64_t>(r) << 1) ^ static_cast<std::uint64_t>(r >> 63);
}
std::int64_t unzigzag64(std::uint64_t u) {
  return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
}

// ---------------------------------------------------------------------------------------------
// Prediction. Everything here depends only on the stencils, so both sides agree without signalling.

// Geometry coding revisions, the section's first byte: 1 = format 1.0 (layout order, no across-patch
// kinds), 2 = format 1.1 (layout order), 3 = format 1.2 (patch order, mixed length models), all still
// decoded; 4 = format 1.3 (either order, named by a flag; revision 3's coding, residual lengths above
// the axis's maximum excluded, no vertex count in the header, compact stream ends); 5 = format 2.1
// (revision 4 plus normal chaining, below); 6 = format 2.2 (revision 4 plus shape transfers, magnitude
// classes from residual magnitudes, a length prior, logistic decisions, and chaining by flag). The
// encoder writes 5 and 6 only where they are smaller, so a file that does not gain still decodes with
// older decoders (and 6 only on sections of up to 32768 vertices).
constexpr std::uint8_t kLayoutRevision = 2;
constexpr std::uint8_t kPatchRevision = 3;
constexpr std::uint8_t kCompactRevision = 4;
constexpr std::uint8_t kChainRevision = 5;
constexpr std::uint8_t kShapeRevision = 6;
constexpr std::uint8_t kNewestRevision = kShapeRevision;

enum Kind : std::uint8_t {
  kNone = 0,
  kWest = 1,
  kLinear = 2,
  kParallelogram = 3,
  kSouth = 4,
  kOpposite = 5,
  kCorners = 6
};

// A vertex's coded neighbours on its grid, (column, row) offsets from it: w (-1,0), ww (-2,0),
// s (0,-1), sw (-1,-1), and derived from other stencils: se (1,-1), ss (0,-2), sww (-2,-1), ssw (-1,-2).
struct Hood {
  std::uint32_t w = kInvalid, ww = kInvalid, s = kInvalid, sw = kInvalid, se = kInvalid, ss = kInvalid,
                sww = kInvalid, ssw = kInvalid;
  const GridLayout::Stencil* t = nullptr;  // its stencil, for the fields `sides` says count
  Kind kind = kNone;
  Kind fallback = kNone;  // for kOpposite / kCorners: the kind it would have along its own edge
  // Context kind: kind, 5 / 6 for kWest / kLinear with a far end, 7 kOpposite, 8 kCorners.
  std::uint8_t ctx = 0;
  // Which of the stencil's far (edge points: the edge's far end, far_dist steps ahead), e/es (patch
  // side ahead along the row, e_dist) and n/nw (along the column, n_dist) count.
  std::uint8_t sides = 0;
  static constexpr std::uint8_t kFar = 1, kEast = 2, kNorth = 4, kOppositeFar = 8;
  bool has(std::uint8_t side) const { return (sides & side) != 0; }
};

constexpr std::uint32_t kMaxFarDist = 64;  // farther ends are ignored (and keep the products small)

// The neighbourhoods of a section's vertices, each computed when the coding loop reaches it (an array
// of them cost 48 bytes a vertex and a pass over memory). Revision 1 (format 1.0) files predate the
// across-patch predictors: their vertices never get kOpposite / kCorners.
class Hoods {
 public:
  Hoods(std::span<const GridLayout::Stencil> st, int revision, CodingOrder order)
      : st_(st), revision_(revision), order_(order) {
    if (order != CodingOrder::kLayout) return;
    // east[x]: the vertex whose w is x and whose s is east of x's s, i.e. x's right neighbour in a grid row.
    east_.assign(st.size(), kInvalid);
    for (std::uint32_t y = 0; y < st.size(); ++y)
      if (full(y)) east_[st[y].w] = y;
  }
  std::uint32_t size() const { return static_cast<std::uint32_t>(st_.size()); }

  Hood operator[](std::uint32_t i) const {
    const GridLayout::Stencil& s = st_[i];
    Hood x;
    // ww and sw only count next to a w (and sw next to an s): a stencil cannot have holes.
    x.w = s.w, x.s = s.s;
    x.ww = s.w != kInvalid ? s.ww : kInvalid;
    x.sw = s.w != kInvalid && s.s != kInvalid ? s.sw : kInvalid;
    if (full(i)) {
      x.kind = kParallelogram;
      if (s.e != kInvalid && s.es != kInvalid && s.e_dist >= 1) x.sides |= Hood::kEast;
      if (s.n != kInvalid && s.nw != kInvalid && s.n_dist >= 1) x.sides |= Hood::kNorth;
      if (order_ == CodingOrder::kPatch) {  // the layout knows the frame across patch sides
        x.se = s.se, x.ss = s.ss, x.sww = s.sww, x.ssw = s.ssw;
      } else {
        const std::uint32_t e = east_[i];
        if (e != kInvalid && st_[e].sw == s.s && st_[e].s < i) x.se = st_[e].s;
        x.ss = st_[s.s].s;
        if (full(s.s)) {
          if (st_[s.s].sw == st_[s.sw].s) x.ssw = st_[s.sw].s;
          if (st_[s.s].ww != kInvalid && st_[s.s].ww == st_[s.sw].w) x.sww = st_[s.sw].w;
        }
      }
    } else if (s.w != kInvalid) {
      x.kind = s.ww != kInvalid ? kLinear : kWest;
      if (s.far != kInvalid && s.far_dist >= 1 && s.far_dist <= kMaxFarDist) x.sides |= Hood::kFar;
      x.fallback = x.kind;
      if (revision_ < kLayoutRevision) {
        // format 1.0: along the edge only
      } else if (s.o != kInvalid && s.ow != kInvalid) {
        x.kind = kOpposite;  // an edge point, also predicted from the patch side across
        if (s.far != kInvalid && s.ofar != kInvalid && s.far_dist >= 1 && s.far_dist <= kMaxFarDist)
          x.sides |= Hood::kOppositeFar;
      } else if (s.x0 != kInvalid && s.x1 != kInvalid &&
                 (s.x2 != kInvalid || (s.xden >= 1 && s.xnum <= s.xden))) {
        x.kind = kCorners;  // a schematic vertex, also predicted from its patch's corners
      }
    } else if (s.s != kInvalid) {
      x.kind = kSouth;
    } else {
      x.kind = kNone;
      x.w = i == 0 ? kInvalid : i - 1;  // the previous vertex stands in for w
    }
    x.t = &s;
    x.ctx = x.kind == kOpposite  ? 7
            : x.kind == kCorners ? 8
            : x.has(Hood::kFar)  ? static_cast<std::uint8_t>(x.kind + 4)
                                 : static_cast<std::uint8_t>(x.kind);
    return x;
  }

 private:
  bool full(std::uint32_t j) const {
    return st_[j].w != kInvalid && st_[j].s != kInvalid && st_[j].sw != kInvalid;
  }
  std::span<const GridLayout::Stencil> st_;
  int revision_;
  CodingOrder order_;
  std::vector<std::uint32_t> east_;  // layout order only
};

// Integer predictors. Blending them helps most where a coarse mesh bends (spot, blub): the
// parallelogram alone misses curvature, the quadratic ones overshoot on noise.
constexpr int kCandidates = 14;  // revision 6; revisions 1-5 have the first 11
constexpr int kOldCandidates = 11;
constexpr std::uint32_t kNoError = 0xFFFFFFFFu;

// Which candidates vertex hood x has all neighbours for (bit k = candidate k).
unsigned candidate_mask(const Hood& x) {
  const bool w = x.w != kInvalid, ww = x.ww != kInvalid, s = x.s != kInvalid, sw = x.sw != kInvalid;
  const bool full = x.kind == kParallelogram;
  const bool se = x.se != kInvalid, ss = x.ss != kInvalid, sww = x.sww != kInvalid, ssw = x.ssw != kInvalid;
  return (w && s && sw) << 0 | (w && ww) << 1 | (w && ww && s && sw && se) << 2 | (s && ss) << 3 |
         (w && ww && s && sw && sww) << 4 | (w && s && sw && ss && ssw) << 5 | w << 6 | (w && se && sw) << 7 |
         (full && x.has(Hood::kEast)) << 8 | (full && x.has(Hood::kNorth)) << 9 |
         (full && x.has(Hood::kEast) && x.has(Hood::kNorth)) << 10;
}

// Revision 6 (`shapes`) adds the shrunk parallelogram (11, with the parallelogram's neighbours) and the
// shape transfers from the west cell (12, with candidate 4's) and the south cell (13, with candidate 5's)
// when every axis is an integer axis; transfer() may still take 12 and 13 away.
unsigned candidate_mask(const Hood& x, bool shapes, bool integer_axes) {
  const unsigned m = candidate_mask(x);
  if (!shapes) return m;
  return m | (m & 1u) << 11 | (integer_axes ? ((m >> 4) & 1u) << 12 | ((m >> 5) & 1u) << 13 : 0u);
}

std::int64_t floor_div(std::int64_t a, std::int64_t b);
__int128 floor_div128(__int128 a, __int128 b);
// How the column step s - sw... at the row's end differs from w's, spread over the e_dist + 1 steps.
std::int64_t row_correction(const Hood& x, const std::int64_t* v) {
  const std::int64_t d = std::int64_t{x.t->e_dist} + 1, c = (v[x.t->e] - v[x.t->es]) - (v[x.w] - v[x.sw]);
  return floor_div(2 * c + d, 2 * d);
}
std::int64_t column_correction(const Hood& x, const std::int64_t* v) {
  const std::int64_t d = std::int64_t{x.t->n_dist} + 1, c = (v[x.t->n] - v[x.t->nw]) - (v[x.s] - v[x.sw]);
  return floor_div(2 * c + d, 2 * d);
}

// The candidates of vertex hood x on one axis (values v) into p[k], for every k in mask (candidate_mask:
// their neighbours exist). Absent neighbours read as 0, so the eight cheap candidates are one straight
// block sharing their loads (a switch per candidate cost an eighth of the encoder); p[k] for k not in
// mask is never used.
void candidates(const Hood& x, const std::int64_t* v, unsigned mask,
                std::array<std::int64_t, kCandidates>& p) {
  auto at = [v](std::uint32_t j) { return j != kInvalid ? v[j] : std::int64_t{0}; };
  const std::int64_t w = at(x.w), ww = at(x.ww), s = at(x.s), sw = at(x.sw), se = at(x.se), ss = at(x.ss);
  p[0] = w + s - sw;                           // parallelogram
  p[1] = 2 * w - ww;                           // linear along the row
  p[2] = 2 * w - ww - 2 * s + sw + se;         // exact on quadratics
  p[3] = 2 * s - ss;                           // linear along the column
  p[4] = 2 * w - ww + s - 2 * sw + at(x.sww);  // parallelogram of row steps
  p[5] = 2 * s - ss + w - 2 * sw + at(x.ssw);  // ... of column steps
  p[6] = w;                                    // west
  p[7] = w + ((se - sw) >> 1);                 // west + central difference below
  // The parallelogram with the column step varying along the row (8), the row step along the column
  // (9), or both (10): candidate 10 needs the neighbours of 8 and 9.
  const std::int64_t r = (mask >> 8) & 1 ? row_correction(x, v) : 0;
  const std::int64_t c = (mask >> 9) & 1 ? column_correction(x, v) : 0;
  p[8] = p[0] + r;
  p[9] = p[0] + c;
  p[10] = p[0] + r + c;
  // Revision 6: the parallelogram shrunk towards sw, for the distorted cells near extraordinary
  // vertices (12 and 13, the shape transfers, come from shape_transfers()).
  if ((mask >> 11) & 1) p[11] = sw + ((13 * (w + s - 2 * sw) + 8) >> 4);
}

// floor(sqrt(n)), exactly.
std::uint64_t isqrt(std::uint64_t n) {
  auto r = static_cast<std::uint64_t>(std::sqrt(static_cast<double>(n)));
  while (r > 0 && (r > 0xFFFFFFFFu || r * r > n)) --r;
  while (r < 0xFFFFFFFFu && (r + 1) * (r + 1) <= n) ++r;
  return r;
}

// Similarity shape transfer (revision 6): a fully coded neighbour cell with corner o2, edges e2 (its row
// step) and f2 (its column step) and opposite corner o2 + d2. Its shape, d2 in the frame of e2 and
// e2 turned a right angle in its plane (the part along its normal dropped), is carried into the frame
// of the cell being coded (corner o, edges e, f), whose opposite corner is predicted. False (no
// prediction) for a degenerate cell or a component of 2^15 or more. Integer only; format spec,
// "Shape transfers".
bool transfer(const std::array<std::int64_t, 3>& o, const std::array<std::int64_t, 3>& e,
              const std::array<std::int64_t, 3>& f, const std::array<std::int64_t, 3>& e2,
              const std::array<std::int64_t, 3>& f2, const std::array<std::int64_t, 3>& d2,
              std::array<std::int64_t, 3>& out) {
  constexpr std::int64_t kLimit = std::int64_t{1} << 15;
  for (int a = 0; a < 3; ++a)
    for (std::int64_t c : {e[a], f[a], e2[a], f2[a], d2[a]})
      if (c <= -kLimit || c >= kLimit) return false;
  auto dot = [](const std::array<std::int64_t, 3>& p, const std::array<std::int64_t, 3>& q) {
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
  };
  const std::int64_t ee2 = dot(e2, e2), ef2 = dot(e2, f2), ee = dot(e, e), ef = dot(e, f);
  // |e x f|^2 = |e|^2 |f|^2 - (e.f)^2 < 2^64 (each component < 2^15)
  const auto area2 =
      static_cast<std::uint64_t>(static_cast<__int128>(ee2) * dot(f2, f2) - __int128{ef2} * ef2);
  const auto area = static_cast<std::uint64_t>(static_cast<__int128>(ee) * dot(f, f) - __int128{ef} * ef);
  if (ee2 == 0 || area2 == 0 || area == 0) return false;
  const __int128 s = static_cast<__int128>(isqrt(area2)) * isqrt(area);
  const std::int64_t pd = dot(d2, e2);
  const __int128 q = static_cast<__int128>(ee2) * dot(d2, f2) - __int128{ef2} * pd;
  const __int128 den = s * ee2;
  for (int a = 0; a < 3; ++a) {
    const __int128 num = __int128{pd} * e[a] * s + q * (__int128{ee} * f[a] - __int128{ef} * e[a]);
    out[a] = o[a] + static_cast<std::int64_t>(floor_div128(2 * num + den, 2 * den));
  }
  return true;
}

std::int64_t floor_div(std::int64_t a, std::int64_t b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
__int128 floor_div128(__int128 a, __int128 b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// Weights of the candidates at a parallelogram vertex: the inverse square of each one's mean error
// at the coded neighbours w, s, sw, se (integer axes summed). 0 for a missing candidate. <= 2^30.
// Returns the magnitude class of the best candidate's mean error: bit_width(floor(4 * mean + 2)).
// nc: the revision's candidate count (a constant, so revisions 1-5 run as fast as before revision 6).
template <int nc>
int blend_weights(const Hood& x, unsigned mask, const std::uint32_t* errors,
                  std::array<std::int64_t, kCandidates>& weight) {
  const std::array<std::uint32_t, 4> near = {x.w, x.s, x.sw, x.se};
  std::uint64_t best = ~std::uint64_t{0};
  for (int k = 0; k < nc; ++k) {
    if (!((mask >> k) & 1)) continue;
    std::uint64_t sum = 0, cnt = 0;
    for (std::uint32_t j : near) {
      if (j == kInvalid || errors[std::size_t{j} * nc + k] == kNoError) continue;
      sum += errors[std::size_t{j} * nc + k];
      ++cnt;
    }
    if (cnt == 0) sum = 1000000, cnt = 1;
    // floor(2^15 cnt / (2 sum + cnt)) and floor((4 sum + 2 cnt) / cnt), without 64-bit divisions
    // (two thirds of this function's time went to them): the first is 0 unless the divisor fits 17
    // bits, and the second divides by cnt = 1..4.
    const std::uint64_t num = (std::uint64_t{1} << 15) * cnt, den = 2 * sum + cnt;
    const auto w =
        den > num
            ? 0
            : static_cast<std::int64_t>(static_cast<std::uint32_t>(num) / static_cast<std::uint32_t>(den));
    weight[k] = w * w;
    const std::uint64_t mean4 = cnt == 1 ? 4 * sum : cnt == 2 ? 2 * sum : cnt == 4 ? sum : 4 * sum / 3;
    best = std::min(best, mean4 + 2);
  }
  return std::bit_width(best);
}

// The weighted mean of the available candidates p[k] (mask bit k), as an offset from the
// parallelogram p[0] (clamped to +-2^28 so the sums cannot overflow), rounded half up. Integer only,
// so exactly reproducible.
template <int nc>  // the revision's candidate count, as for blend_weights
std::int64_t blend(const std::array<std::int64_t, kCandidates>& p, unsigned mask,
                   const std::array<std::int64_t, kCandidates>& weight) {
  std::int64_t num = 0, den = 0;
  for (int k = 0; k < nc; ++k) {
    if (!((mask >> k) & 1)) continue;
    num += weight[k] * std::clamp<std::int64_t>(p[k] - p[0], -(1 << 28), 1 << 28);
    den += weight[k];
  }
  return den == 0 ? p[0] : p[0] + floor_div(2 * num + den, 2 * den);
}

// Normal chaining (revision 5, and 6 by its flag). Where a scan is remeshed, the blend misses mostly along
// the surface normal (60% of the residual energy on QuadriFlow's gargoyle at 14 bits), so a blended vertex's
// three residuals are correlated. Axes 1 and 2 are predicted from the residuals before them, as the mean of
// a normal distribution with covariance B I + A n n^T: n is the normal of the plane through w, s and
// sw, A and B are running energies of past residuals along n and across it. Where residuals are
// isotropic A is 0 and nothing changes. Integer only; format spec, "Normal chaining".
class NormalChain {
 public:
  static constexpr std::int64_t kClamp = std::int64_t{1} << 14;  // residuals are clamped to +-kClamp

  // Starts vertex hood x (kParallelogram) with integer axes `ints`.
  explicit NormalChain(bool wide) : wide_(wide) {}  // wide: revision 6's normal and decay
  void start(const Hood& x, const std::array<std::vector<std::int64_t>, 3>& ints) {
    std::array<std::int64_t, 3> d1, d2;
    std::uint64_t span = 0;
    // Revision 6 takes the row step centred on the vertex's column, se - sw, where se is coded.
    const bool centred = wide_ && x.se != kInvalid;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t* v = ints[a].data();
      d1[a] = v[x.w] - v[x.sw];
      d2[a] = (centred ? v[x.se] : v[x.s]) - v[x.sw];
      span |= abs64(d1[a]) | abs64(d2[a]);
    }
    if (span < (std::uint64_t{1} << 31)) {  // 64-bit products suffice
      set_normal<std::int64_t>(d1, d2);
    } else {
      set_normal<__int128>(d1, d2);
    }
    const std::uint64_t across = (across_ >> 1) + 1, along = along_ > across ? along_ - across : 0;
    const int scale = std::max(0, static_cast<int>(std::bit_width(std::max(along, across))) - 15);
    a_ = static_cast<std::int64_t>(along >> scale);
    b_ = static_cast<std::int64_t>(across >> scale) + 1;
  }

  // Whether the running energies say residuals lie mostly along the normal here (A > T / 2, T the
  // across energy): the encoder's cue that chaining may pay (encode_best).
  bool anisotropic() const { return 2 * a_ > b_ - 1; }

  // What to add to axis `axis`'s prediction, given the residuals recorded for the axes before it.
  std::int64_t offset(int axis) const {
    if (axis == 0 || a_ == 0 || norm2_ == 0) return 0;
    std::int64_t dot = 0, known2 = 0;
    for (int k = 0; k < axis; ++k) dot += m_[k] * raw_[k], known2 += m_[k] * m_[k];
    const std::int64_t den = b_ * norm2_ + a_ * known2;
    return floor_div(2 * (a_ * m_[axis] * dot) + den, 2 * den);
  }

  // Axis `axis`'s residual against the blend (for a quantized axis already taken modulo 2^bits).
  void record(int axis, std::int64_t r) { raw_[axis] = std::clamp(r, -kClamp, kClamp); }

  // Ends the vertex: its residuals join the running energies (each decays by 1/32 a vertex).
  void finish() {
    if (norm2_ == 0) return;
    std::int64_t dot = 0;
    std::uint64_t total = 0;
    for (int a = 0; a < 3; ++a) {
      dot += m_[a] * raw_[a];
      total += static_cast<std::uint64_t>(raw_[a] * raw_[a]);
    }
    const std::uint64_t along = std::min(static_cast<std::uint64_t>(dot * dot / norm2_), total);
    const int dc = wide_ ? 4 : 5;  // revision 6 adapts twice as fast
    along_ = along_ - (along_ >> dc) + along;
    across_ = across_ - (across_ >> dc) + (total - along);
  }

 private:
  static std::uint64_t abs64(std::int64_t v) {
    return v < 0 ? 0 - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
  }
  // m_ = d1 x d2, shifted right (floor) until every |m_a| <= 2^15; T holds the exact cross product.
  template <typename T>
  void set_normal(const std::array<std::int64_t, 3>& d1, const std::array<std::int64_t, 3>& d2) {
    const std::array<T, 3> m = {T{d1[1]} * d2[2] - T{d1[2]} * d2[1], T{d1[2]} * d2[0] - T{d1[0]} * d2[2],
                                T{d1[0]} * d2[1] - T{d1[1]} * d2[0]};
    T big = 0;
    for (const T c : m) big |= c < 0 ? -c : c;
    const auto hi = static_cast<std::uint64_t>(sizeof(T) > 8 ? big >> 63 >> 1 : 0);  // below 2^19
    const int width = hi ? 64 + static_cast<int>(std::bit_width(hi))
                         : static_cast<int>(std::bit_width(static_cast<std::uint64_t>(big)));
    const int shift = std::max(0, width - 15);
    norm2_ = 0;
    for (int a = 0; a < 3; ++a) {
      m_[a] = static_cast<std::int64_t>(m[a] >> shift);
      norm2_ += m_[a] * m_[a];
    }
  }
  bool wide_;                             // revision 6
  std::uint64_t along_ = 0, across_ = 0;  // running energies: sum of (r.n)^2, of |r|^2 - (r.n)^2
  std::array<std::int64_t, 3> m_{};       // the plane's normal, |m_a| <= 2^15
  std::int64_t norm2_ = 0;                // |m|^2; 0 for a degenerate plane (no chaining)
  std::int64_t a_ = 0, b_ = 1;            // the model's A and B, scaled to at most 2^15 (b_ >= 1)
  std::array<std::int64_t, 3> raw_{};     // this vertex's residuals against the blend, clamped
};

// The magnitude class coding vertex i: the mean residual length of its w and s neighbours.
int bucket_for(const std::uint8_t* lengths, const Hood& x) {
  int v = 0;
  if (x.w != kInvalid && x.s != kInvalid) {
    v = (lengths[x.w] + lengths[x.s] + 1) >> 1;
  } else if (x.w != kInvalid) {
    v = lengths[x.w];
  } else if (x.s != kInvalid) {
    v = lengths[x.s];
  }
  return std::min(v, kBuckets - 1);
}

// The fixed predictor of kinds other than kParallelogram, and of float axes.
std::int64_t predict_kind(const Hood& x, Kind kind, const std::int64_t* v) {
  switch (kind) {
    case kParallelogram:
      return v[x.w] + v[x.s] - v[x.sw];
    case kLinear:
      if (x.has(Hood::kFar)) {  // the quadratic through ww (-2), w (-1) and far (D), at 0
        const std::int64_t d = x.t->far_dist, den = (d + 1) * (d + 2);
        const std::int64_t num = -d * (d + 1) * v[x.ww] + 2 * d * (d + 2) * v[x.w] + 2 * v[x.t->far];
        return floor_div(2 * num + den, 2 * den);
      }
      return 2 * v[x.w] - v[x.ww];
    case kWest:
      if (x.has(Hood::kFar)) {  // the line through w (-1) and far (D), at 0
        const std::int64_t d = x.t->far_dist;
        return floor_div(2 * (d * v[x.w] + v[x.t->far]) + d + 1, 2 * (d + 1));
      }
      return v[x.w];
    case kSouth:
      return v[x.s];
    case kNone:
      return x.w == kInvalid ? 0 : v[x.w];
    case kOpposite: {
      const GridLayout::Stencil& t = *x.t;
      if (x.has(Hood::kOppositeFar)) {  // the offset to the side across, interpolated between w and far
        const std::int64_t d = t.far_dist;
        return v[t.o] + floor_div(2 * (d * (v[x.w] - v[t.ow]) + (v[t.far] - v[t.ofar])) + d + 1, 2 * (d + 1));
      }
      return v[x.w] + v[t.o] - v[t.ow];
    }
    case kCorners: {
      const GridLayout::Stencil& t = *x.t;
      if (t.x2 != kInvalid) return v[t.x1] + v[t.x2] - v[t.x0];
      const __int128 num = static_cast<__int128>(v[t.x1] - v[t.x0]) * t.xnum;
      return v[t.x0] + static_cast<std::int64_t>(floor_div128(2 * num + t.xden, 2 * __int128{t.xden}));
    }
  }
  return 0;
}

// Order-preserving image of float bits: negative floats reversed below the positive ones.
std::uint32_t float_image(float f) {
  const std::uint32_t u = std::bit_cast<std::uint32_t>(f);
  return u ^ ((u >> 31) ? 0xFFFFFFFFu : 0x80000000u);
}
float image_float(std::uint32_t m) {
  return std::bit_cast<float>(m ^ ((m >> 31) ? 0x80000000u : 0xFFFFFFFFu));
}

// Float-axis prediction: additions in binary64 (no products, so no FMA contraction can change it),
// rounded once to binary32; if that is not finite (a NaN/inf operand or overflow), w's own bits.
std::uint32_t predict_float(const Hood& x, Kind kind, const float* f) {
  double d;
  switch (kind) {
    case kParallelogram:
      d = (double{f[x.w]} + double{f[x.s]}) - double{f[x.sw]};
      break;
    case kLinear:
      d = (double{f[x.w]} + double{f[x.w]}) - double{f[x.ww]};
      break;
    case kWest:
      return float_image(f[x.w]);
    case kSouth:
      return float_image(f[x.s]);
    case kOpposite:
      d = (double{f[x.w]} + double{f[x.t->o]}) - double{f[x.t->ow]};
      break;
    case kCorners:
      if (x.t->x2 == kInvalid) return float_image(f[x.w]);
      d = (double{f[x.t->x1]} + double{f[x.t->x2]}) - double{f[x.t->x0]};
      break;
    default:
      return x.w == kInvalid ? float_image(0.0f) : float_image(f[x.w]);
  }
  const float r = static_cast<float>(d);
  return std::isfinite(r) ? float_image(r) : float_image(f[x.w]);
}

// ---------------------------------------------------------------------------------------------
// Decimal grids: float = the binary32 nearest to n / 10^k (ties to even), exactly what
// std::from_chars gives for the decimal text.

constexpr int kMaxDecimals = 9;
constexpr std::int64_t kDecimalLimit = std::int64_t{1} << 40;  // |n| < 2^40
constexpr std::array<double, kMaxDecimals + 1> kPow10 = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};

float decimal_float_slow(std::int64_t n, int k) {
  char buf[40];
  auto [end, ec] = std::to_chars(buf, buf + 30, n);
  (void)ec;
  *end++ = 'e';
  *end++ = '-';
  *end++ = static_cast<char>('0' + k);
  float f = 0;
  std::from_chars(buf, end, f);
  return f;
}

// n / 10^k in binary64 is correctly rounded (both exact); rounding that to binary32 is then correct
// unless it landed exactly on a midpoint between two floats, which the slow path settles.
float decimal_float(std::int64_t n, int k) {
  const double d = static_cast<double>(n) / kPow10[k];
  const float f = static_cast<float>(d);
  if (static_cast<double>(f) != d) {
    const float g = std::nextafter(
        f, d > f ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity());
    if ((static_cast<double>(f) + static_cast<double>(g)) * 0.5 == d) return decimal_float_slow(n, k);
  }
  return f;
}

// The decimal integer for x at k decimals, or false if x is not exactly such a value.
bool decimal_of(float x, int k, std::int64_t& n) {
  if (!std::isfinite(x)) return false;
  const double scaled = static_cast<double>(x) * kPow10[k];
  if (!(std::fabs(scaled) < static_cast<double>(kDecimalLimit) - 1)) return false;
  n = std::llround(scaled);
  if (n == 0 && std::signbit(x)) return false;  // -0 has no decimal integer
  return std::bit_cast<std::uint32_t>(decimal_float(n, k)) == std::bit_cast<std::uint32_t>(x);
}

// ---------------------------------------------------------------------------------------------
// Section layout

enum AxisMode : std::uint8_t { kFloatBits = 0 };  // 1 + k: decimal grid with k decimals

constexpr int kFloatMaxLength = 33;    // zigzag of an image difference in (-2^32, 2^32)
constexpr int kDecimalMaxLength = 42;  // zigzag of n - clamp(prediction), both |.| < 2^40

struct Exception {
  std::uint32_t vertex;
  float value;
};

struct AxisPlan {
  std::uint8_t mode = kFloatBits;
  bool trailing_zeros = false;  // decimal only: code each integer's trailing zero digits first
  std::vector<Exception> exceptions;
};

constexpr std::uint8_t kTrailingFlag = 0x80;  // in the axis mode byte
constexpr int kMaxTrailing = kMaxTrailingZeros;
constexpr std::array<std::int64_t, kMaxTrailing + 1> kPow10i = {
    1,        10,        100,        1000,        10000,        100000,       1000000,
    10000000, 100000000, 1000000000, 10000000000, 100000000000, 1000000000000};

int trailing_zeros(std::int64_t n) {
  int t = 0;
  while (n != 0 && t < kMaxTrailing && n % 10 == 0) n /= 10, ++t;
  return t;
}

int decimal_digits(std::int64_t n) {  // of |n|; 0 for 0
  int d = 0;
  for (std::uint64_t m = static_cast<std::uint64_t>(n < 0 ? -n : n); m != 0; m /= 10) ++d;
  return d;
}

// Trailing-zero coding pays when the zeros follow the magnitude, as with "%g" output (6 significant
// digits: 0.348799 and 0.0663178 share k = 7, but the first ends in a zero): estimate the cost of
// coding t given the digit count against the log2(10^t) bits it saves.
bool trailing_zeros_pay(std::span<const float> pos, int axis, int k) {
  std::array<std::array<double, kMaxTrailing + 1>, 16> counts{};
  double saved = 0, total = 0;
  std::int64_t n;
  for (std::size_t i = axis; i < pos.size(); i += 3) {
    if (!decimal_of(pos[i], k, n)) continue;
    const int t = trailing_zeros(n);
    counts[std::min(decimal_digits(n), 15)][t] += 1;
    saved += t * std::log2(10.0);
    total += 1;
  }
  double cost = 0;
  for (const auto& row : counts) {
    double sum = 0;
    for (double c : row) sum += c;
    for (double c : row)
      if (c > 0) cost -= c * std::log2(c / sum);
  }
  return saved > cost + 0.25 * total;
}

void check_stencil(std::span<const GridLayout::Stencil> stencil, std::size_t n) {
  if (stencil.size() != n) throw Error(ErrorCode::kInternal, "geometry: stencil count != vertex count");
  for (std::uint32_t i = 0; i < n; ++i) {
    // j >= i for a field j other than kInvalid, i.e. j + 1 > i with kInvalid wrapping to 0: no branch
    // per field (this check was 3% of encoding).
    bool forward = false;
    for (std::uint32_t j : stencil[i].vertex_fields()) forward |= j + 1 > i;
    if (forward) throw Error(ErrorCode::kInternal, "geometry: stencil refers forward");
  }
}

// Exceptions it would take to store axis `axis` at k decimals, stopping past `limit`.
std::size_t decimal_misses(std::span<const float> pos, int axis, int k, std::size_t limit) {
  std::size_t misses = 0;
  std::int64_t n;
  for (std::size_t i = axis; i < pos.size(); i += 3) {
    if (!decimal_of(pos[i], k, n) && ++misses > limit) break;
  }
  return misses;
}

// Cheapest decimal grid for the axis, or float bits. Estimates bits: a decimal step of 10^-k costs
// about log2(ulp(x) * 10^k) bits more per coordinate than the float's own ulp; a miss ~40 bits.
AxisPlan plan_axis(std::span<const float> pos, int axis) {
  const std::size_t count = pos.size() / 3;
  double log_ulp_sum = 0;  // sum of log2(ulp(x)) over finite x
  for (std::size_t i = axis; i < pos.size(); i += 3) {
    const float x = std::fabs(pos[i]);
    if (!std::isfinite(x)) continue;
    const int e = x < std::numeric_limits<float>::min() ? -126 : std::ilogb(x);
    log_ulp_sum += e - 23;
  }
  double best_cost = 0;  // float bits, relative
  int best_k = -1;
  for (int k = 0; k <= kMaxDecimals; ++k) {
    const double grid = count * k * std::log2(10.0) + log_ulp_sum;  // bits vs float mode
    const double budget = (best_cost - grid) / 40.0;
    if (budget < 0) continue;
    const std::size_t misses = decimal_misses(pos, axis, k, static_cast<std::size_t>(budget));
    const double cost = grid + 40.0 * static_cast<double>(misses);
    if (cost < best_cost) {
      best_cost = cost;
      best_k = k;
    }
    if (misses == 0) break;  // more decimals only cost more
  }
  AxisPlan plan;
  if (best_k < 0) return plan;
  plan.mode = static_cast<std::uint8_t>(1 + best_k);
  plan.trailing_zeros = trailing_zeros_pay(pos, axis, best_k);
  std::int64_t n;
  for (std::uint32_t i = 0; i < count; ++i) {
    const float x = pos[3 * i + axis];
    if (!decimal_of(x, best_k, n)) plan.exceptions.push_back({i, x});
  }
  return plan;
}

std::int64_t clamp_decimal(std::int64_t p) { return std::clamp(p, -(kDecimalLimit - 1), kDecimalLimit - 1); }

// Quantization grid. step has at most 23 significant bits so q * step (q < 2^30) is exact in binary64.
struct Grid {
  std::array<float, 3> origin{};
  double step = 0;
  float value(int axis, std::int64_t q) const {
    return static_cast<float>(static_cast<double>(origin[axis]) + static_cast<double>(q) * step);
  }
  // Nearest grid integer, clamped to the grid, and never one that decodes to infinity.
  std::int64_t quantize(int axis, float x, std::uint32_t bits) const {
    if (step == 0) return 0;
    const double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
    auto q =
        static_cast<std::int64_t>(std::clamp(std::nearbyint((double{x} - origin[axis]) / step), 0.0, top));
    while (q > 0 && !std::isfinite(value(axis, q))) --q;
    return q;
  }
};

constexpr std::uint64_t kStepLowMask = (std::uint64_t{1} << 30) - 1;  // fraction bits that must be zero

Grid make_grid(std::span<const float> pos, std::uint32_t bits) {
  Grid g;
  double extent = 0;
  for (int a = 0; a < 3; ++a) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (std::size_t i = a; i < pos.size(); i += 3) {
      if (!std::isfinite(pos[i])) {
        throw Error(ErrorCode::kBadNumber, "geometry: cannot quantize a NaN or infinite coordinate");
      }
      lo = std::min(lo, pos[i]);
      hi = std::max(hi, pos[i]);
    }
    if (pos.empty()) lo = hi = 0;
    g.origin[a] = lo == 0 ? 0.0f : lo;  // no -0 origin: it adds nothing
    extent = std::max(extent, static_cast<double>(hi) - static_cast<double>(lo));
  }
  if (extent > 0) {
    const double ideal = extent / static_cast<double>((std::uint64_t{1} << bits) - 1);
    std::uint64_t b = std::bit_cast<std::uint64_t>(ideal);
    b = (b + kStepLowMask) & ~kStepLowMask;  // round up: keeps every q <= 2^bits - 1
    g.step = std::bit_cast<double>(b);
  }
  return g;
}

// ---------------------------------------------------------------------------------------------
// Coding loop, shared by encoder and decoder so the two cannot drift apart.

constexpr std::uint8_t kRepeatsFlag = 0x01;      // header flags (revision >= 2): value repeats coded
constexpr std::uint8_t kLayoutOrderFlag = 0x02;  // revisions 4-6: layout order (else patch order)
constexpr std::uint8_t kChainFlag = 0x04;        // revision 6: normal chaining (revision 5 always chains)

// The coding order of a section of this revision with these header flags.
CodingOrder coding_order(int revision, std::uint8_t flags) {
  if (revision >= kCompactRevision)
    return (flags & kLayoutOrderFlag) ? CodingOrder::kLayout : CodingOrder::kPatch;
  return revision == kPatchRevision ? CodingOrder::kPatch : CodingOrder::kLayout;
}

struct Header {
  int revision = kCompactRevision;          // or kChainRevision, kShapeRevision
  bool chain = false;                       // normal chaining: revision 5, or 6 with kChainFlag
  CodingOrder order = CodingOrder::kPatch;  // revisions 1, 2: layout; 3: patch; 4-6: its flag
  std::uint32_t bits = 0;                   // 0 lossless, else quantized
  bool repeats = false;  // a coordinate may be coded as "the k-th closest value seen on its axis"
  std::array<AxisPlan, 3> plans;
  Grid grid;
  bool integer_axis(int a) const { return bits != 0 || plans[a].mode != kFloatBits; }
  bool integer_axes() const { return integer_axis(0) && integer_axis(1) && integer_axis(2); }  // chainable
  int max_length(int a) const {
    return bits ? static_cast<int>(bits) : plans[a].mode == kFloatBits ? kFloatMaxLength : kDecimalMaxLength;
  }
  // The payload's residual model and stream ends, as the revision has them (encoder and decoder alike).
  ResidualModel model() const {
    ResidualModel m(revision >= kPatchRevision, revision >= kCompactRevision);
    if (revision >= kShapeRevision) m.set_prior(), m.set_logistic();
    return m;
  }
  StreamEnds ends() const { return revision >= kCompactRevision ? StreamEnds::kCompact : StreamEnds::kLzma; }
};

// Values already coded on one axis, for coordinates that repeat one exactly (CAD cages, symmetric
// and revolved shapes: OpenSubdiv's pawn repeats 77% of its coordinates). Candidates are ranked by
// distance to the prediction (ties: the smaller value first), so a repeat costs the rank of the
// value among those about as close, usually 0 or 1. Decoder side: the values in order, in sorted
// blocks of at most kBlock (a std::set cost 2x the whole lossless decode of a 222k-vertex scan), the
// blocks in pages of at most kPage: with one flat list of blocks, every split moved all the blocks
// after it (16M distinct values inserted in descending order: 23 s; now 1.1 s).
class Repeats {
 public:
  static constexpr std::uint32_t kMaxRank = 63;  // 255 saved 0.1% more and walked 4x as far
  bool empty() const { return pages_.empty(); }
  void insert(std::int64_t v) {
    if (pages_.empty()) {
      pages_.push_back({{{v}}, {v}});
      page_last_.push_back(v);
      return;
    }
    std::size_t p = page_of(v);
    if (p == pages_.size()) --p;  // beyond every page: append to the last
    Page& page = pages_[p];
    std::size_t b = block_in(page, v);
    if (b == page.blocks.size()) --b;
    std::vector<std::int64_t>& blk = page.blocks[b];
    auto it = std::lower_bound(blk.begin(), blk.end(), v);
    if (it != blk.end() && *it == v) return;
    blk.insert(it, v);
    page.last[b] = blk.back();
    if (blk.size() > kBlock) {  // split the block in two halves, within its page
      std::vector<std::int64_t> upper(blk.begin() + kBlock / 2, blk.end());
      blk.resize(kBlock / 2);
      page.last[b] = blk.back();
      page.last.insert(page.last.begin() + static_cast<std::ptrdiff_t>(b) + 1, upper.back());
      page.blocks.insert(page.blocks.begin() + static_cast<std::ptrdiff_t>(b) + 1, std::move(upper));
    }
    page_last_[p] = page.last.back();
    if (page.blocks.size() > kPage) {  // split the page in two halves
      Page upper;
      upper.blocks.assign(std::make_move_iterator(page.blocks.begin() + kPage / 2),
                          std::make_move_iterator(page.blocks.end()));
      upper.last.assign(page.last.begin() + kPage / 2, page.last.end());
      page.blocks.resize(kPage / 2);
      page.last.resize(kPage / 2);
      page_last_[p] = page.last.back();
      page_last_.insert(page_last_.begin() + static_cast<std::ptrdiff_t>(p) + 1, upper.last.back());
      pages_.insert(pages_.begin() + static_cast<std::ptrdiff_t>(p) + 1, std::move(upper));
    }
  }
  // The value of rank k; false if there are not that many.
  bool nth(std::int64_t pred, std::uint32_t k, std::int64_t& v) const {
    // hi = first value >= pred, lo = the one before it, as (page, block, index) cursors; (pages, 0) is
    // the end.
    Cursor h{page_of(pred), 0, 0};
    if (h.page < pages_.size()) {
      const Page& page = pages_[h.page];
      h.block = block_in(page, pred);
      const auto& blk = page.blocks[h.block];
      h.index = static_cast<std::size_t>(std::lower_bound(blk.begin(), blk.end(), pred) - blk.begin());
    }
    Cursor l = h;  // its index points one past the next lower value
    for (std::uint32_t i = 0;; ++i) {
      while (l.index == 0 && (l.page > 0 || l.block > 0)) {
        if (l.block > 0) {
          --l.block;
        } else {
          --l.page;
          l.block = pages_[l.page].blocks.size() - 1;
        }
        l.index = pages_[l.page].blocks[l.block].size();
      }
      const bool has_lo = l.index > 0, has_hi = h.page < pages_.size();
      if (!has_lo && !has_hi) return false;
      bool take_lo = has_lo;
      if (has_lo && has_hi) take_lo = pred - at(l, l.index - 1) <= at(h, h.index) - pred;
      std::int64_t c;
      if (take_lo) {
        c = at(l, --l.index);
      } else {
        c = at(h, h.index++);
        if (h.index == pages_[h.page].blocks[h.block].size()) {
          h.index = 0;
          if (++h.block == pages_[h.page].blocks.size()) ++h.page, h.block = 0;
        }
      }
      if (i == k) {
        v = c;
        return true;
      }
    }
  }

 private:
  static constexpr std::size_t kBlock = 256, kPage = 256;
  struct Page {
    std::vector<std::vector<std::int64_t>> blocks;  // sorted, disjoint, in order; none empty
    std::vector<std::int64_t> last;                 // each block's largest value
  };
  struct Cursor {
    std::size_t page, block, index;
  };
  std::int64_t at(const Cursor& c, std::size_t index) const { return pages_[c.page].blocks[c.block][index]; }
  // The first page (block of `page`) whose last value is >= v (the count if none).
  std::size_t page_of(std::int64_t v) const {
    return static_cast<std::size_t>(std::lower_bound(page_last_.begin(), page_last_.end(), v) -
                                    page_last_.begin());
  }
  static std::size_t block_in(const Page& page, std::int64_t v) {
    return static_cast<std::size_t>(std::lower_bound(page.last.begin(), page.last.end(), v) -
                                    page.last.begin());
  }
  std::vector<Page> pages_;              // sorted, disjoint, in order; none empty
  std::vector<std::int64_t> page_last_;  // each page's largest value
};

// Encoder side: every value the axis will insert is known up front, so a Fenwick tree over their
// sorted distinct list gives a rank in O(log n); walking the set would cost hundreds of steps per
// coordinate on dense axes (4-decimal scans).
class RepeatRanks {
 public:
  RepeatRanks() = default;
  explicit RepeatRanks(std::vector<std::int64_t> values) : sorted_(std::move(values)) {
    std::sort(sorted_.begin(), sorted_.end());
    sorted_.erase(std::unique(sorted_.begin(), sorted_.end()), sorted_.end());
    tree_.assign(sorted_.size() + 1, 0);
    in_.assign(sorted_.size(), 0);
  }
  bool empty() const { return count_ == 0; }
  void insert(std::int64_t v) {
    const std::size_t i = index(v);
    if (i == sorted_.size() || sorted_[i] != v)
      throw Error(ErrorCode::kInternal, "geometry: unplanned repeat value");
    if (in_[i]) return;
    in_[i] = 1, ++count_;
    for (std::size_t j = i + 1; j < tree_.size(); j += j & (~j + 1)) ++tree_[j];
  }
  // The rank of `v` from `pred` (values strictly closer, and as close but smaller), or
  // Repeats::kMaxRank + 1 if `v` is not in the set or ranks beyond that.
  std::uint32_t rank_of(std::int64_t pred, std::int64_t v) const {
    constexpr std::uint32_t kMiss = Repeats::kMaxRank + 1;
    const std::size_t i = index(v);
    if (i == sorted_.size() || sorted_[i] != v || !in_[i]) return kMiss;
    const std::int64_t d = v >= pred ? v - pred : pred - v;
    if (d == 0) return 0;
    std::size_t k = below(index(pred + d)) - below(index(pred - d + 1));
    if (v > pred) {  // pred - d is as close and smaller: it ranks first
      const std::size_t j = index(pred - d);
      if (j < sorted_.size() && sorted_[j] == pred - d && in_[j]) ++k;
    }
    return static_cast<std::uint32_t>(std::min<std::size_t>(k, kMiss));
  }

 private:
  std::size_t index(std::int64_t v) const {
    return static_cast<std::size_t>(std::lower_bound(sorted_.begin(), sorted_.end(), v) - sorted_.begin());
  }
  std::size_t below(std::size_t i) const {  // inserted values among sorted_[0 .. i)
    std::size_t sum = 0;
    for (; i > 0; i -= i & (~i + 1)) sum += tree_[i];
    return sum;
  }
  std::vector<std::int64_t> sorted_;
  std::vector<std::uint32_t> tree_;  // Fenwick tree, 1-based
  std::vector<std::uint8_t> in_;
  std::size_t count_ = 0;
};

// One decision group of the geometry stream, as the encoder's coding loop produces it.
struct Symbol {
  enum Op : std::uint8_t { kResidual, kZeros, kRepeat };
  std::uint64_t value;  // residual u (kResidual), trailing zeros t (kZeros), rank (kRepeat)
  Op op;
  std::uint8_t ctx;   // kind context (kResidual, kRepeat)
  std::uint8_t arg;   // magnitude bucket (kResidual), digit count (kZeros), previous axis (kRepeat)
  std::uint8_t arg2;  // the axis's maximum length (kResidual), taken or not (kRepeat)
  std::uint8_t axis = 0, cls = 0, prev = 0;  // kResidual, revision 6: the mixer's other contexts
};

void code_symbol(const Symbol& s, ResidualModel& m, RangeEncoder& rc) {
  switch (s.op) {
    case Symbol::kResidual: {
      const Extra e{s.axis, s.cls, s.prev};
      m.encode(rc, s.value, s.ctx, s.arg, s.arg2, &e);
      break;
    }
    case Symbol::kZeros:
      m.encode_zeros(rc, static_cast<int>(s.value), s.arg);
      break;
    case Symbol::kRepeat:
      rc.encode_bit(m.repeat[std::size_t{s.ctx} * 3 + s.arg], s.arg2);
      if (s.arg2) m.rank.encode(rc, static_cast<std::uint32_t>(s.value));
      break;
  }
}

// Where the encoder's coding loop puts its symbols: coded at once, or (large sections) handed in blocks
// to a second thread that codes them while the loop predicts the next vertices. The model's state never
// feeds back into prediction, so both give the same bytes. The second thread takes the range coder off
// the critical path: bench_geometry on mh_female_generic_cc2 (2 cores), 14 bits 167 -> 145 ms,
// lossless 395 -> 357 ms.
class SymbolSink {
 public:
  // Codes into `payload`, with the stream ends of h's revision.
  SymbolSink(const Header& h, std::string& payload, bool threaded)
      : payload_(payload), coder_(std::make_unique<Coder>(h)) {
    if (!threaded || std::thread::hardware_concurrency() == 1) return;  // one core: a thread only costs
    block_.reserve(kBlock);  // before the thread: once it runs, nothing here may throw
    try {
      thread_ = std::thread([this] { run(); });
    } catch (const std::system_error&) {
      // no thread to be had: code on this one
    }
  }
  SymbolSink(const SymbolSink&) = delete;
  SymbolSink& operator=(const SymbolSink&) = delete;
  ~SymbolSink() {  // on an exception in the coding loop: stop the coder unheard
    if (!thread_.joinable()) return;
    {
      std::lock_guard lock(mutex_);
      done_ = true;
      full_.clear();
    }
    ready_.notify_all();
    thread_.join();
  }

  void put(const Symbol& s) {
    if (!thread_.joinable()) return code_symbol(s, coder_->model, coder_->rc);
    block_.push_back(s);
    if (block_.size() == kBlock) hand_over();
  }

  // Codes what is left and ends the stream into the payload; rethrows what failed the coder thread.
  void finish() {
    if (thread_.joinable()) {
      hand_over();
      {
        std::lock_guard lock(mutex_);
        done_ = true;
      }
      ready_.notify_all();
      thread_.join();
      if (error_) std::rethrow_exception(error_);
    }
    coder_->rc.finish();
    payload_ = std::move(coder_->bytes);
  }

 private:
  static constexpr std::size_t kBlock = 16384;  // symbols (256 KiB)
  static constexpr std::size_t kMaxQueued = 8;  // blocks the loop may run ahead: bounds the memory

  void hand_over() {
    std::vector<Symbol> next;
    {
      std::unique_lock lock(mutex_);
      taken_.wait(lock, [this] { return full_.size() < kMaxQueued || error_; });
      if (error_) return block_.clear();  // finish() rethrows it
      full_.push_back(std::move(block_));
      if (!empty_.empty()) next = std::move(empty_.back()), empty_.pop_back();
    }
    ready_.notify_one();
    block_ = std::move(next);
    block_.clear();
    block_.reserve(kBlock);
  }

  void run() {
    std::unique_lock lock(mutex_);
    for (;;) {
      ready_.wait(lock, [this] { return !full_.empty() || done_; });
      if (full_.empty()) return;
      std::vector<Symbol> block = std::move(full_.front());
      full_.pop_front();
      lock.unlock();
      taken_.notify_one();
      try {
        for (const Symbol& s : block) code_symbol(s, coder_->model, coder_->rc);
      } catch (...) {
        lock.lock();
        error_ = std::current_exception();
        full_.clear();
        taken_.notify_all();
        return;
      }
      block.clear();
      lock.lock();
      empty_.push_back(std::move(block));
    }
  }

  // The coder's state, on its own cache lines: on the coding loop's stack its every symbol missed the
  // coder thread's cache, and coding took twice as long as on one thread.
  struct alignas(64) Coder {
    explicit Coder(const Header& h) : model(h.model()), rc(bytes, h.ends()) {}
    ResidualModel model;
    std::string bytes;
    RangeEncoder rc;  // into bytes
  };

  std::string& payload_;
  std::unique_ptr<Coder> coder_;
  std::vector<Symbol> block_;  // being filled by the coding loop
  std::thread thread_;
  std::mutex mutex_;  // guards the members below
  std::condition_variable ready_, taken_;
  std::deque<std::vector<Symbol>> full_;  // blocks waiting to be coded, in order
  std::vector<std::vector<Symbol>> empty_;
  bool done_ = false;
  std::exception_ptr error_;
};

// A coordinate as a repeat of a value seen on its axis: the decision (context: the vertex's kind and how
// its previous axis went) and, if taken, the rank (code_symbol codes it). Encoder: true if `value` is
// coded as a repeat, with the symbol in `sym`. Decoder: true and `value` set if the stream says it is one.
template <bool kEncode>
bool repeat(ResidualModel* m, const RepeatRanks& ranks, const Repeats& seen, int ctx, int previous,
            std::int64_t pred, std::int64_t& value, Symbol* sym, RangeDecoder* dec) {
  if (kEncode ? ranks.empty() : seen.empty()) return false;
  if constexpr (kEncode) {
    const std::uint32_t k = ranks.rank_of(pred, value);
    // Stricter rules (rank 0 only, rank small against the residual) were measured worse overall.
    const bool hit = k <= Repeats::kMaxRank;
    *sym = {k, Symbol::kRepeat, static_cast<std::uint8_t>(ctx), static_cast<std::uint8_t>(previous), hit};
    return hit;
  } else {
    BitModel& flag = m->repeat[static_cast<std::size_t>(ctx) * 3 + previous];
    if (!dec->decode_bit(flag)) return false;
    const std::uint32_t k = m->rank.decode(*dec);
    if (k > Repeats::kMaxRank || !seen.nth(pred, k, value)) fail("repeat rank out of range");
    return true;
  }
}

// A quantized residual modulo 2^bits (qmax = 2^bits - 1), taken in [-2^(bits-1), 2^(bits-1)).
std::int64_t wrapped(std::int64_t r, std::int64_t qmax) {
  r &= qmax;
  return r > qmax / 2 ? r - (qmax + 1) : r;
}

// Revision 6's shape transfers at vertex hood x (mask: its candidates) into shape[0] (the west cell's,
// candidate 12) and shape[1] (the south cell's, 13). Returns the mask bits of those with no prediction.
unsigned shape_transfers(const Hood& x, const std::array<std::vector<std::int64_t>, 3>& v, unsigned mask,
                         std::array<std::array<std::int64_t, 3>, 2>& shape) {
  auto at = [&v](std::uint32_t j) { return std::array<std::int64_t, 3>{v[0][j], v[1][j], v[2][j]}; };
  auto sub = [](const std::array<std::int64_t, 3>& p, const std::array<std::int64_t, 3>& q) {
    return std::array<std::int64_t, 3>{p[0] - q[0], p[1] - q[1], p[2] - q[2]};
  };
  const std::array<std::int64_t, 3> w = at(x.w), s = at(x.s), sw = at(x.sw);
  const std::array<std::int64_t, 3> e = sub(s, sw), f = sub(w, sw);
  // The similarity that keeps the row step's shape and the one that keeps the column step's, averaged.
  auto similar = [&](const std::array<std::int64_t, 3>& e2, const std::array<std::int64_t, 3>& f2,
                     const std::array<std::int64_t, 3>& d2, std::array<std::int64_t, 3>& out) {
    std::array<std::int64_t, 3> p, q;
    if (!transfer(sw, e, f, e2, f2, d2, p) || !transfer(sw, f, e, f2, e2, d2, q)) return false;
    for (int a = 0; a < 3; ++a) out[a] = (p[a] + q[a] + 1) >> 1;
    return true;
  };
  unsigned off = 0;
  if ((mask >> 12) & 1) {  // the west cell: sww, sw (its row step), ww (its column step), w
    const std::array<std::int64_t, 3> sww = at(x.sww);
    if (!similar(sub(sw, sww), sub(at(x.ww), sww), sub(w, sww), shape[0])) off |= 1u << 12;
  }
  if ((mask >> 13) & 1) {  // the south cell: ssw, ss (its row step), sw (its column step), s
    const std::array<std::int64_t, 3> ssw = at(x.ssw);
    if (!similar(sub(at(x.ss), ssw), sub(sw, ssw), sub(s, ssw), shape[1])) off |= 1u << 13;
  }
  return off;
}

// Revision 6's magnitude class for axis `a` of blended vertex i: the bit width of twice the weighted mean
// of the coded values u of its neighbours on the axis (w and s weigh 2, sw and se 1) and of its own
// earlier axes (2 each), into `pure`; returned mixed 3:1 with the blend's class. Residual magnitudes
// follow the local distortion more closely than lengths do (gargoyle -65 bytes at 14 bits).
int magnitude_class(const std::array<std::vector<std::uint32_t>, 3>& mags, const Hood& x, std::uint32_t i,
                    int a, int blend_class, int& pure) {
  const std::uint32_t* m = mags[a].data();
  std::uint64_t sum = 2 * (std::uint64_t{m[x.w]} + m[x.s]) + m[x.sw], weight = 5;
  if (x.se != kInvalid) sum += m[x.se], ++weight;
  for (int b = 0; b < a; ++b) sum += 2 * std::uint64_t{mags[b][i]}, weight += 2;
  const int cls = static_cast<int>(std::bit_width(2 * sum / weight));
  pure = std::min(kBuckets - 1, cls);
  return std::min(kBuckets - 1, (3 * cls + blend_class + 2) >> 2);
}

// Encoder statistics of a section coded without chaining: its kind-3 vertices, and how many of them
// the chaining model found anisotropic (NormalChain::anisotropic). encode_best tries revision 5 only
// where that is over a fifth: elsewhere it gained at most a few bytes on the shared meshes.
struct ChainCue {
  std::uint32_t vertices = 0, anisotropic = 0;
};

// Encoder: `ints` holds each integer axis's integers (decimal exceptions are set to their
// prediction here) and `floats` each float axis's floats. Decoder: both are filled, and `out` gets the
// floats. `shapes`: revision 6 (a template argument, so revisions 1-5 pay nothing for it).
template <bool kEncode, bool shapes>
void code_vertices(const Header& h, const Hoods& hoods, std::uint32_t count,
                   std::array<std::vector<std::int64_t>, 3>& ints, std::array<std::vector<float>, 3>& floats,
                   SymbolSink* sink, RangeDecoder* dec, std::vector<float>* out, ChainCue* cue = nullptr) {
  const bool any_int = h.integer_axis(0) || h.integer_axis(1) || h.integer_axis(2);
  constexpr int nc = shapes ? kCandidates : kOldCandidates;
  std::vector<std::uint32_t> errors(any_int ? std::size_t{count} * nc : 0, kNoError);
  std::array<std::vector<std::uint8_t>, 3> lengths;
  for (auto& l : lengths) l.assign(count, 0);
  std::array<std::vector<std::uint32_t>, 3> mags;  // revision 6: each coded value u, at most 2^32 - 1
  if constexpr (shapes)
    for (auto& m : mags) m.assign(count, 0);
  std::array<std::array<std::int64_t, 3>, 2> shape{};  // the two transfers' predictions
  std::array<std::size_t, 3> next_exception{};
  const std::int64_t qmax = h.bits ? static_cast<std::int64_t>((std::uint64_t{1} << h.bits) - 1) : 0;
  // The decoder's model; the encoder's is the sink's.
  const auto model = kEncode ? nullptr : std::make_unique<ResidualModel>(h.model());
  Symbol repeat_sym{};  // the encoder's repeat decision for the current axis, if it made one (op kRepeat)
  std::array<std::int64_t, kCandidates> weight{};
  std::array<std::array<std::int64_t, kCandidates>, 3> cand{};
  // Across-patch vertices: running means (x16) of the errors of the across prediction [0] and of the
  // prediction along the vertex's own edge [1], per class; the one with the smaller mean is used.
  // (Blending the two was worse: on CAD-like meshes the across prediction is often exact.)
  std::array<std::array<std::uint64_t, 2>, 4> across_err{};
  std::array<std::array<std::int64_t, 2>, 3> across_pred{};
  NormalChain chain(shapes);
  const bool chaining = h.chain && h.integer_axes();
  // The chaining model runs (its offsets only if chaining) for the decoder and for the encoder's cue.
  const bool modelled = h.integer_axes() && (chaining || cue);
  std::array<Repeats, 3> seen;       // decoder
  std::array<RepeatRanks, 3> ranks;  // encoder
  if (kEncode && h.repeats) {
    for (int a = 0; a < 3; ++a) {
      std::vector<std::int64_t> values;
      values.reserve(count);
      const std::vector<Exception>* ex = h.integer_axis(a) && !h.bits ? &h.plans[a].exceptions : nullptr;
      std::size_t e = 0;
      for (std::uint32_t i = 0; i < count; ++i) {
        if (ex && e < ex->size() && (*ex)[e].vertex == i) {
          ++e;  // exceptions are never repeats
          continue;
        }
        values.push_back(h.integer_axis(a) ? ints[a][i]
                                           : static_cast<std::int64_t>(float_image(floats[a][i])));
      }
      ranks[a] = RepeatRanks(std::move(values));
    }
  }
  for (std::uint32_t i = 0; i < count; ++i) {
    int previous = 0;  // how the vertex's previous axis was coded: 0 none / no repeats, 1 residual, 2 repeat
    const Hood x = hoods[i];
    unsigned mask = any_int ? candidate_mask(x, shapes, h.integer_axes()) : 0;
    if constexpr (shapes) {
      if (mask >> 12) mask &= ~shape_transfers(x, ints, mask, shape);
    }
    const bool blended = any_int && x.kind == kParallelogram;
    const int blend_class = blended ? blend_weights<nc>(x, mask, errors.data(), weight) : 0;
    const bool across = x.kind == kOpposite || x.kind == kCorners;
    // Its across class (format spec): which running means it uses.
    const int cls = !across               ? 0
                    : x.kind == kOpposite ? (x.has(Hood::kOppositeFar) ? 0 : 1)
                                          : (x.t->x2 != kInvalid ? 2 : 3);
    for (int a = 0; a < 3; ++a) {
      if (!h.integer_axis(a)) continue;
      candidates(x, ints[a].data(), mask, cand[a]);
      if constexpr (shapes) cand[a][12] = shape[0][a], cand[a][13] = shape[1][a];
    }
    const bool chained = modelled && blended;
    if (chained) {
      chain.start(x, ints);
      if (cue) ++cue->vertices, cue->anisotropic += chain.anisotropic();
    }
    std::array<std::int64_t, 3> blended_pred{};
    for (int a = 0; a < 3; ++a) {
      // Magnitude class: neighbours' residual lengths, averaged with the blend's expected error.
      int bucket = bucket_for(lengths[a].data(), x);
      int pure = bucket;  // revision 6: the neighbours' class alone
      if (blended) {
        bucket = shapes ? magnitude_class(mags, x, i, a, blend_class, pure)
                        : std::min(kBuckets - 1, (bucket + blend_class + 1) >> 1);
      }
      int prev_len = 0;  // revision 6: the length of the vertex's previous axis
      if constexpr (shapes) prev_len = a == 0 ? 0 : std::min<int>(kBuckets - 1, lengths[a - 1][i]);
      const Extra extra{a, pure, prev_len};  // revision 6 (the decoder's; the encoder's goes in its Symbol)
      std::uint64_t u = 0;
      bool hit = false;            // coded as a repeat
      bool candidate = true;       // may be a repeat, and joins the values seen (not a decimal exception)
      int zeros = -1, digits = 0;  // trailing-zero coding: t, and the digit count of |prediction|
      if (h.integer_axis(a)) {
        std::int64_t* v = ints[a].data();
        std::int64_t pred;
        if (blended) {
          pred = blended_pred[a] = blend<nc>(cand[a], mask, weight);
          if (chaining) pred += chain.offset(a);
        } else if (across) {
          const std::int64_t pa = predict_kind(x, x.kind, v), pf = predict_kind(x, x.fallback, v);
          across_pred[a] = {pa, pf};
          pred = across_err[cls][0] <= across_err[cls][1] ? pa : pf;
        } else {
          pred = predict_kind(x, x.kind, v);
        }
        if (h.bits) {
          pred = std::clamp<std::int64_t>(pred, 0, qmax);
          hit = h.repeats && repeat<kEncode>(model.get(), ranks[a], seen[a], x.ctx, previous, pred, v[i],
                                             &repeat_sym, dec);
          if (kEncode || hit) {
            // (For a repeat: only for the neighbours' magnitude classes.)
            u = zigzag64(wrapped(v[i] - pred, qmax));
          } else {
            u = model->decode(*dec, x.ctx, bucket, h.max_length(a), shapes ? &extra : nullptr);
            v[i] = (pred + unzigzag64(u)) & qmax;
          }
          if constexpr (!kEncode) (*out)[3 * std::size_t{i} + a] = h.grid.value(a, v[i]);
        } else {
          pred = clamp_decimal(pred);
          const AxisPlan& plan = h.plans[a];
          std::size_t& e = next_exception[a];
          const bool exception = e < plan.exceptions.size() && plan.exceptions[e].vertex == i;
          // With trailing-zero coding, n = 10^t * m: residual of m against the rounded prediction.
          if (plan.trailing_zeros) digits = std::min(decimal_digits(pred), 15);
          if constexpr (kEncode) {
            if (exception) v[i] = pred;  // its float is stored aside: residual zero keeps neighbours smooth
          }
          candidate = !exception;
          if ((hit = h.repeats && candidate &&
                     repeat<kEncode>(model.get(), ranks[a], seen[a], x.ctx, previous, pred, v[i], &repeat_sym,
                                     dec))) {
            u = zigzag64(v[i] - pred);
            if constexpr (!kEncode) {
              (*out)[3 * std::size_t{i} + a] =
                  exception ? plan.exceptions[e].value : decimal_float(v[i], plan.mode - 1);
            }
          } else if constexpr (kEncode) {
            if (plan.trailing_zeros) {
              zeros = trailing_zeros(v[i]);
              const std::int64_t unit = kPow10i[zeros];
              u = zigzag64(v[i] / unit - floor_div(2 * pred + unit, 2 * unit));
            } else {
              u = zigzag64(v[i] - pred);
            }
          } else {
            u = model->decode(*dec, x.ctx, bucket, h.max_length(a), shapes ? &extra : nullptr);
            if (plan.trailing_zeros) {
              const int t = model->decode_zeros(*dec, digits);
              const std::int64_t unit = kPow10i[t];
              const std::int64_t m = floor_div(2 * pred + unit, 2 * unit) + unzigzag64(u);
              // |m * 10^t| < 2^40; 10^t does not divide 2^40 for t > 0, so compare against (2^40 - 1) / 10^t.
              if (m < -((kDecimalLimit - 1) / unit) || m > (kDecimalLimit - 1) / unit)
                fail("decimal integer out of range");
              v[i] = m * unit;
            } else {
              v[i] = pred + unzigzag64(u);
            }
            if (v[i] <= -kDecimalLimit || v[i] >= kDecimalLimit) fail("decimal integer out of range");
            (*out)[3 * std::size_t{i} + a] =
                exception ? plan.exceptions[e].value : decimal_float(v[i], plan.mode - 1);
          }
          if (exception) ++e;
        }
      } else {
        float* f = floats[a].data();
        std::int64_t pred = predict_float(x, x.kind, f);
        if (across) {
          const std::int64_t pf = predict_float(x, x.fallback, f);
          across_pred[a] = {pred, pf};
          if (across_err[cls][0] > across_err[cls][1]) pred = pf;
        }
        std::int64_t image = 0;
        if constexpr (kEncode) image = float_image(f[i]);
        hit = h.repeats &&
              repeat<kEncode>(model.get(), ranks[a], seen[a], x.ctx, previous, pred, image, &repeat_sym, dec);
        if (kEncode || hit) {
          u = zigzag64(image - pred);
        } else {
          u = model->decode(*dec, x.ctx, bucket, h.max_length(a), shapes ? &extra : nullptr);
          image = pred + unzigzag64(u);
          if (image < 0 || image > 0xFFFFFFFFll) fail("float residual out of range");
        }
        if constexpr (!kEncode) {
          f[i] = image_float(static_cast<std::uint32_t>(image));
          (*out)[3 * std::size_t{i} + a] = f[i];
        }
      }
      if constexpr (kEncode) {
        if (repeat_sym.op == Symbol::kRepeat) sink->put(repeat_sym), repeat_sym = {};
        if (!hit) {
          sink->put({u, Symbol::kResidual, x.ctx, static_cast<std::uint8_t>(bucket),
                     static_cast<std::uint8_t>(h.max_length(a)), static_cast<std::uint8_t>(a),
                     static_cast<std::uint8_t>(pure), static_cast<std::uint8_t>(prev_len)});
        }
        if (zeros >= 0)
          sink->put(
              {static_cast<std::uint64_t>(zeros), Symbol::kZeros, 0, static_cast<std::uint8_t>(digits), 0});
      }
      lengths[a][i] = static_cast<std::uint8_t>(std::bit_width(u));
      if constexpr (shapes) mags[a][i] = static_cast<std::uint32_t>(std::min<std::uint64_t>(u, 0xFFFFFFFFu));
      if (chained) {
        const std::int64_t r = ints[a][i] - blended_pred[a];
        chain.record(a, h.bits ? wrapped(r, qmax) : r);
      }
      if (h.repeats) {
        if (candidate) {
          const std::int64_t value =
              h.integer_axis(a) ? ints[a][i] : static_cast<std::int64_t>(float_image(floats[a][i]));
          if constexpr (kEncode) {
            ranks[a].insert(value);
          } else {
            seen[a].insert(value);
          }
        }
        previous = hit ? 2 : 1;
      }
    }
    if (across) {
      for (int p = 0; p < 2; ++p) {
        std::uint64_t err = 0;
        for (int a = 0; a < 3; ++a) {
          if (any_int && !h.integer_axis(a)) continue;
          const std::int64_t value =
              h.integer_axis(a) ? ints[a][i] : static_cast<std::int64_t>(float_image(floats[a][i]));
          err += static_cast<std::uint64_t>(
              std::min<std::int64_t>(std::abs(value - across_pred[a][p]), kNoError));
        }
        across_err[cls][p] += err - (across_err[cls][p] >> 4);
      }
    }
    if (chained) chain.finish();
    if (!any_int) continue;
    for (int k = 0; k < nc; ++k) {
      std::uint32_t& slot = errors[std::size_t{i} * nc + k];
      if (!((mask >> k) & 1)) continue;  // stays kNoError
      std::uint64_t err = 0;
      for (int a = 0; a < 3; ++a)
        if (h.integer_axis(a))
          err +=
              static_cast<std::uint64_t>(std::min<std::int64_t>(std::abs(ints[a][i] - cand[a][k]), kNoError));
      slot = static_cast<std::uint32_t>(std::min<std::uint64_t>(err, kNoError - 1));
    }
  }
}

void write_header(std::string& out, const Header& h, std::uint32_t count) {
  put_u8(out, static_cast<std::uint8_t>(h.revision));
  if (h.revision < kCompactRevision) put_varint(out, count);
  put_u8(out, static_cast<std::uint8_t>(h.bits));
  std::uint8_t flags = h.repeats ? kRepeatsFlag : 0;
  if (h.revision >= kCompactRevision && h.order == CodingOrder::kLayout) flags |= kLayoutOrderFlag;
  if (h.revision >= kShapeRevision && h.chain) flags |= kChainFlag;
  put_u8(out, flags);
  if (h.bits) {
    for (float o : h.grid.origin) put_le(out, std::bit_cast<std::uint32_t>(o), 4);
    put_le(out, std::bit_cast<std::uint64_t>(h.grid.step), 8);
    return;
  }
  for (const AxisPlan& plan : h.plans) {
    put_u8(out, plan.mode | (plan.trailing_zeros ? kTrailingFlag : 0));
    if (plan.mode == kFloatBits) continue;
    put_varint(out, plan.exceptions.size());
    std::uint32_t prev = 0;
    for (std::size_t e = 0; e < plan.exceptions.size(); ++e) {
      const Exception& x = plan.exceptions[e];
      put_varint(out, e == 0 ? x.vertex : x.vertex - prev - 1);
      put_le(out, std::bit_cast<std::uint32_t>(x.value), 4);
      prev = x.vertex;
    }
  }
}

Header read_header(Reader& in, std::uint32_t count) {
  Header h;
  h.revision = in.u8("truncated header");
  if (h.revision < 1 || h.revision > kNewestRevision) fail("unknown geometry coding revision");
  if (h.revision < kCompactRevision && in.varint("truncated vertex count") != count)
    fail("vertex count does not match the mesh");
  h.bits = in.u8("truncated header");
  if (h.bits > 30) fail("quantization bits out of range");
  std::uint8_t flags = 0;
  if (h.revision >= kLayoutRevision) {
    flags = in.u8("truncated header");
    const std::uint8_t known = h.revision >= kShapeRevision     ? kRepeatsFlag | kLayoutOrderFlag | kChainFlag
                               : h.revision >= kCompactRevision ? kRepeatsFlag | kLayoutOrderFlag
                                                                : kRepeatsFlag;
    if (flags & ~known) fail("reserved geometry flag bits are set");
    h.repeats = (flags & kRepeatsFlag) != 0;
  }
  h.chain = h.revision == kChainRevision || (flags & kChainFlag) != 0;
  h.order = coding_order(h.revision, flags);
  if (h.bits) {
    for (float& o : h.grid.origin) {
      o = std::bit_cast<float>(static_cast<std::uint32_t>(in.le(4, "truncated grid origin")));
      if (!std::isfinite(o)) fail("grid origin not finite");
    }
    h.grid.step = std::bit_cast<double>(in.le(8, "truncated grid step"));
    if (!std::isfinite(h.grid.step) || std::signbit(h.grid.step) ||
        (std::bit_cast<std::uint64_t>(h.grid.step) & kStepLowMask)) {
      fail("invalid grid step");
    }
    return h;
  }
  for (AxisPlan& plan : h.plans) {
    plan.mode = in.u8("truncated axis mode");
    plan.trailing_zeros = (plan.mode & kTrailingFlag) != 0;
    plan.mode &= static_cast<std::uint8_t>(~kTrailingFlag);
    if (plan.mode > 1 + kMaxDecimals || (plan.trailing_zeros && plan.mode == kFloatBits))
      fail("unknown axis mode");
    if (plan.mode == kFloatBits) continue;
    const std::uint64_t n = in.varint("truncated exception count");
    if (n > count || n > in.left() / 5) fail("exception count exceeds the data");
    plan.exceptions.resize(n);
    std::uint64_t prev = 0;
    for (std::uint64_t e = 0; e < n; ++e) {
      const std::uint64_t gap = in.varint("truncated exception");
      const std::uint64_t v = e == 0 ? gap : prev + 1 + gap;
      if (gap >= count || v >= count) fail("exception vertex out of range");
      plan.exceptions[e].vertex = static_cast<std::uint32_t>(v);
      plan.exceptions[e].value =
          std::bit_cast<float>(static_cast<std::uint32_t>(in.le(4, "truncated exception")));
      prev = v;
    }
  }
  return h;
}

// The section for the first `count` vertices (stencils only look back, so a prefix codes on its own).
std::string encode_with(std::span<const float> pos, const Hoods& hoods, std::uint32_t count, const Header& h,
                        std::optional<bool> coder_thread, ChainCue* cue = nullptr) {
  std::array<std::vector<std::int64_t>, 3> ints;
  std::array<std::vector<float>, 3> floats;
  for (int a = 0; a < 3; ++a) {
    if (!h.integer_axis(a)) {
      floats[a].resize(count);
      for (std::uint32_t i = 0; i < count; ++i) floats[a][i] = pos[3 * std::size_t{i} + a];
      continue;
    }
    ints[a].resize(count);
    const std::vector<Exception>& ex = h.plans[a].exceptions;
    std::size_t e = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      const float x = pos[3 * std::size_t{i} + a];
      std::int64_t v = 0;
      if (h.bits) {
        v = h.grid.quantize(a, x, h.bits);
      } else if (e < ex.size() && ex[e].vertex == i) {
        ++e;  // set to its prediction while coding
      } else {
        decimal_of(x, h.plans[a].mode - 1, v);
      }
      ints[a][i] = v;
    }
  }
  std::string out;
  write_header(out, h, count);
  std::string payload;
  {
    SymbolSink sink(h, payload, coder_thread.value_or(count > kCoderThreadAbove));
    if (h.revision >= kShapeRevision) {
      code_vertices<true, true>(h, hoods, count, ints, floats, &sink, nullptr, nullptr, cue);
    } else {
      code_vertices<true, false>(h, hoods, count, ints, floats, &sink, nullptr, nullptr, cue);
    }
    sink.finish();
  }
  put_varint(out, payload.size());
  out += payload;
  return out;
}

// Header h with normal chaining (revision 5; with_shapes() keeps it in revision 6), if its axes are all
// integer axes (else there is nothing to chain) and `cue`, from coding with h, says it may pay.
std::optional<Header> chained(const Header& h, const ChainCue& cue) {
  if (!h.integer_axes()) return std::nullopt;
  if (std::uint64_t{cue.anisotropic} * 5 <= cue.vertices) return std::nullopt;
  Header c = h;
  if (c.revision < kChainRevision) c.revision = kChainRevision;
  c.chain = true;
  return c;
}

// Header h in revision 6, keeping its chaining.
Header with_shapes(Header h) {
  h.revision = kShapeRevision;
  return h;
}

// The smallest of the candidate headers (value repeats on and off; for lossless, the decimal plan and
// plain float bits): repeats pay on CAD-like meshes (pawn -37% at 14 bits) and cost a few percent where
// coordinates only repeat by chance. Then the best one with normal chaining, if that is smaller
// (`o.try_chaining`): one more encode, not one per header, and only where the best one's ChainCue says it
// may pay (chaining gains on remeshed scans and is neutral elsewhere). With `o.header_sample` the
// choice is made on the first that many vertices (stencils only look back, so a prefix codes on its
// own), scaling the payload to the whole section, and the section is coded once. Last, a section whose
// headers were tried in full tries the winner in revision 6 and keeps it where smaller (`o.shapes`);
// with a sample it keeps revision 4 or 5 unless revision 6 is forced: they decode with half the
// instructions (mh_female_generic_cc2 at 14 bits: 1.56 against 2.98 G for the whole decompress, for
// 1.6% fewer bytes). `chosen` gets the index of the header it chose (before chaining).
std::string encode_best(std::span<const float> pos, const Hoods& hoods, const std::vector<Header>& options,
                        const GeometryOptions& o, std::size_t& chosen) {
  const std::uint32_t count = hoods.size();
  const std::optional<bool> coder_thread = o.coder_thread;
  chosen = 0;
  if (o.header_sample == 0 || count <= o.header_sample) {
    std::string best;
    ChainCue best_cue;
    for (std::size_t i = 0; i < options.size(); ++i) {
      ChainCue cue;
      std::string bytes = encode_with(pos, hoods, count, options[i], coder_thread, &cue);
      if (best.empty() || bytes.size() < best.size()) best = std::move(bytes), chosen = i, best_cue = cue;
    }
    Header final = options[chosen];
    if (const std::optional<Header> c = o.try_chaining ? chained(options[chosen], best_cue) : std::nullopt) {
      std::string bytes = encode_with(pos, hoods, count, *c, coder_thread);
      if (bytes.size() < best.size()) best = std::move(bytes), final = *c;
    }
    if (o.shapes.value_or(true)) {
      std::string bytes = encode_with(pos, hoods, count, with_shapes(final), coder_thread);
      if (bytes.size() < best.size() || o.shapes == true) best = std::move(bytes);
    }
    return best;
  }
  const std::uint32_t sample = o.header_sample;
  const double scale = static_cast<double>(count) / sample;
  const Header* best = nullptr;
  double best_size = 0;
  auto estimate = [&](const Header& h, ChainCue* cue) {
    std::string head;
    write_header(head, h, count);
    return static_cast<double>(head.size()) +
           scale * static_cast<double>(encode_with(pos, hoods, sample, h, false, cue).size() - head.size());
  };
  ChainCue best_cue;
  if (options.size() == 1 && !o.try_chaining) {
    best = &options[0];  // nothing to choose
  } else {
    for (std::size_t i = 0; i < options.size(); ++i) {
      ChainCue cue;
      double size = estimate(options[i], &cue);
      if (o.repeats_must_pay && options[i].repeats) size += size / 31;  // saves 1/32 of it, or lose
      if (!best || size < best_size) best = &options[i], best_size = size, best_cue = cue, chosen = i;
    }
  }
  Header final = *best;
  if (const std::optional<Header> c = o.try_chaining ? chained(*best, best_cue) : std::nullopt;
      c && estimate(*c, nullptr) < best_size)
    final = *c;
  if (o.shapes.value_or(false)) final = with_shapes(final);
  return encode_with(pos, hoods, count, final, coder_thread);
}

}  // namespace

std::string encode_geometry(std::span<const float> positions, std::span<const GridLayout::Stencil> stencil,
                            const GeometryOptions& options, GeometryChoice* chosen) {
  if (positions.size() % 3 != 0) throw Error(ErrorCode::kUsage, "geometry: positions not a multiple of 3");
  if (positions.size() / 3 > std::numeric_limits<std::uint32_t>::max() - 1) {
    throw Error(ErrorCode::kLimit, "geometry: too many vertices");
  }
  if (options.quantize_bits > 30) throw Error(ErrorCode::kUsage, "geometry: quantize_bits must be 0..30");
  check_stencil(stencil, positions.size() / 3);
  Header h;
  h.order = options.order;
  const Hoods hoods(stencil, h.revision, h.order);
  std::vector<Header> headers;
  std::vector<GeometryChoice> choices;  // what each header is, in GeometryChoice's terms
  if (options.quantize_bits) {
    h.bits = options.quantize_bits;
    h.grid = make_grid(positions, h.bits);
    headers = {h};
    choices = {{}};
  } else {
    for (int a = 0; a < 3; ++a) h.plans[a] = plan_axis(positions, a);
    const bool decimal =
        std::any_of(h.plans.begin(), h.plans.end(), [](const AxisPlan& p) { return p.mode != kFloatBits; });
    headers = {h};
    choices = {{false, decimal}};
    // The decimal estimate is a heuristic: never do worse than plain float bits.
    if (decimal) {
      headers.push_back(Header{});
      headers.back().order = h.order;
      choices.push_back({false, false});
    }
  }
  for (std::size_t i = 0, n = headers.size(); i < n; ++i) {
    headers.push_back(headers[i]);
    headers.back().repeats = true;
    choices.push_back({true, choices[i].decimal});
  }
  if (options.choice) {  // only the header chosen (all of them if none matches)
    std::vector<Header> kept;
    std::vector<GeometryChoice> kept_choices;
    for (std::size_t i = 0; i < headers.size(); ++i) {
      if (choices[i].repeats != options.choice->repeats || choices[i].decimal != options.choice->decimal)
        continue;
      kept.push_back(headers[i]);
      kept_choices.push_back(choices[i]);
    }
    if (!kept.empty()) headers = std::move(kept), choices = std::move(kept_choices);
  }
  std::size_t best = 0;
  std::string bytes = encode_best(positions, hoods, headers, options, best);
  if (chosen) *chosen = choices[best];
  return bytes;
}

std::vector<float> decode_geometry(std::string_view bytes, std::span<const GridLayout::Stencil> stencil,
                                   std::uint32_t vertex_count) {
  check_stencil(stencil, vertex_count);
  Reader in(bytes);
  const Header h = read_header(in, vertex_count);
  const std::uint64_t payload_size = in.varint("truncated payload size");
  if (payload_size != in.left()) fail("payload size does not match the section");
  RangeDecoder rc(in.take(payload_size, "truncated payload"), 0, "geometry: payload", h.ends());
  const Hoods hoods(stencil, h.revision, h.order);
  std::array<std::vector<std::int64_t>, 3> ints;
  std::array<std::vector<float>, 3> floats;
  for (int a = 0; a < 3; ++a)
    (h.integer_axis(a) ? ints[a].resize(vertex_count) : floats[a].resize(vertex_count));
  std::vector<float> out(std::size_t{vertex_count} * 3);
  if (h.revision >= kShapeRevision) {
    code_vertices<false, true>(h, hoods, vertex_count, ints, floats, nullptr, &rc, &out);
  } else {
    code_vertices<false, false>(h, hoods, vertex_count, ints, floats, nullptr, &rc, &out);
  }
  rc.finish();
  return out;
}

CodingOrder geometry_coding_order(std::string_view bytes) {
  if (bytes.empty()) fail("truncated header");
  const auto revision = static_cast<std::uint8_t>(bytes[0]);
  if (revision < 1 || revision > kNewestRevision) fail("unknown geometry coding revision");
  if (revision < kCompactRevision) return coding_order(revision, 0);  // named by the revision alone
  if (bytes.size() < 3) fail("truncated header");                     // revision, bits, flags
  return coding_order(revision, static_cast<std::uint8_t>(bytes[2]));
}

float decimal_grid_value(std::int64_t n, int k) {
  if (k < 0 || k > kMaxDecimals || n <= -kDecimalLimit || n >= kDecimalLimit) {
    throw Error(ErrorCode::kInternal, "geometry: decimal grid value out of range");
  }
  return decimal_float(n, k);
}

double max_geometry_error(std::span<const float> original, std::span<const float> decoded) {
  if (original.size() != decoded.size()) throw Error(ErrorCode::kInternal, "geometry: size mismatch");
  double worst = 0;
  for (std::size_t i = 0; i < original.size(); ++i) {
    if (std::bit_cast<std::uint32_t>(original[i]) == std::bit_cast<std::uint32_t>(decoded[i])) continue;
    const double d = std::fabs(static_cast<double>(original[i]) - static_cast<double>(decoded[i]));
    if (std::isnan(d)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, d);
  }
  return worst;
}

}  // namespace qsp
