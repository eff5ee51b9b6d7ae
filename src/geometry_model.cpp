// The geometry section's residual model: see geometry_model.h. Here: its tables, the length prior, and
// the trailing-zero counts.
#include "geometry_model.h"

#include "geometry_values.h"

namespace qsp {

// kCodedNodes is indexed by an axis's largest valid length.
static_assert(kFloatMaxLength < 64 && kDecimalMaxLength < 64);

ResidualModel::ResidualModel(bool logistic)
    : logistic_(logistic),
      length_(std::size_t{kContextKinds} * kClasses * 64),
      general_(std::size_t{kContextKinds} * 64),
      mantissa_(64 * 4),
      zeros_(16 * 16),
      repeat_(std::size_t{kContextKinds} * 3) {
  if (!logistic) return;
  by_class_.resize(std::size_t{kContextKinds} * 3 * kClasses * 64);
  by_previous_.resize(std::size_t{kContextKinds} * 3 * kClasses * 64);
  length_weights_.resize(2 * 64);
  mantissa_bucket_.resize(std::size_t{64} * kClasses * 4);
  mantissa_kind_.resize(std::size_t{64} * kContextKinds * 4);
  mantissa_class_.resize(std::size_t{64} * 3 * kClasses * 4);
  mantissa_weights_.resize(2 * 4);
  set_prior();
}

// Each class's length tree starts from a distribution centred on the class, as if it had seen 3 bits: a
// length d below the class weighs 2^-d, d above it 2^-3d (residuals spread downwards from the typical
// length, rarely upwards). Spec, "Length prior".
void ResidualModel::set_prior() {
  static const std::vector<std::uint16_t> prior = [] {  // [class][node 1..63]
    std::vector<std::uint16_t> p(std::size_t{kClasses} * 64);
    for (int b = 0; b < kClasses; ++b) {
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
  for (int kind = 0; kind < kContextKinds; ++kind) {
    for (int b = 0; b < kClasses; ++b) {
      BitModel* tree = length_tree(kind, b);
      for (std::size_t node = 1; node < 64; ++node) {
        const std::uint16_t p = prior[static_cast<std::size_t>(b) * 64 + node];
        tree[node] = BitModel{p, p, 3};
      }
    }
  }
}

void ResidualModel::encode_zeros(RangeEncoder& rc, int t, int digits) {
  BitModel* tree = &zeros_[static_cast<std::size_t>(digits) * 16];
  for (int i = 3, node = 1; i >= 0; --i) {
    const unsigned b = (t >> i) & 1;
    rc.encode_bit(tree[node], b);
    node = 2 * node + static_cast<int>(b);
  }
}

int ResidualModel::decode_zeros(RangeDecoder& rc, int digits) {
  BitModel* tree = &zeros_[static_cast<std::size_t>(digits) * 16];
  int node = 1;
  for (int i = 0; i < 4; ++i) node = 2 * node + static_cast<int>(rc.decode_bit(tree[node]));
  return node - 16 > kMaxTrailingZeros ? -1 : node - 16;
}

}  // namespace qsp
