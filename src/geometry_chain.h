// Normal chaining (format-spec/geometry_section.md, "Normal chaining"), the normal chaining tool. Where
// a scan is remeshed, the blend misses mostly along the surface normal (60% of the residual energy on
// QuadriFlow's gargoyle at 14 bits), so a full cell's three residuals are correlated. Axes 1 and 2 are
// predicted also from the residuals before them, as the mean of a normal distribution with covariance
// B I + A n n^T: n is the normal of the cell (through w, sw and se, else s), A and B running energies of
// past residuals along n and across it. Where residuals are isotropic A is 0 and nothing changes.
// Integer only.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "geometry_hood.h"
#include "geometry_values.h"

namespace qsp {

class NormalChain {
 public:
  static constexpr std::int64_t kClamp = std::int64_t{1} << 14;  // residuals are clamped to +-kClamp

  // Starts vertex hood x (kParallelogram) with integer axes `ints`.
  void start(const Hood& x, const std::array<std::vector<std::int64_t>, 3>& ints) {
    std::array<std::int64_t, 3> d1, d2;
    std::uint64_t span = 0;
    // The row step centred on the vertex's column, se - sw, where se is coded.
    const std::uint32_t row = x.se != kInvalid ? x.se : x.s;
    for (std::size_t a = 0; a < 3; ++a) {
      const std::int64_t* v = ints[a].data();
      d1[a] = v[x.w] - v[x.sw];
      d2[a] = v[row] - v[x.sw];
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
  // across energy): the encoder's cue that chaining may pay.
  bool anisotropic() const { return 2 * a_ > b_ - 1; }

  // What to add to axis `axis`'s prediction, given the residuals recorded for the axes before it.
  std::int64_t offset(int axis) const {
    if (axis == 0 || a_ == 0 || norm2_ == 0) return 0;
    std::int64_t dot = 0, known2 = 0;
    for (std::size_t k = 0; k < static_cast<std::size_t>(axis); ++k)
      dot += m_[k] * raw_[k], known2 += m_[k] * m_[k];
    const std::int64_t den = b_ * norm2_ + a_ * known2;
    return floor_div(2 * (a_ * m_[static_cast<std::size_t>(axis)] * dot) + den, 2 * den);
  }

  // Axis `axis`'s residual against the blend (for a quantized axis already taken modulo 2^bits).
  void record(int axis, std::int64_t r) {
    raw_[static_cast<std::size_t>(axis)] = std::clamp(r, -kClamp, kClamp);
  }

  // Ends the vertex: its residuals join the running energies (each decays by 1/16 a vertex).
  void finish() {
    if (norm2_ == 0) return;
    std::int64_t dot = 0;
    std::uint64_t total = 0;
    for (std::size_t a = 0; a < 3; ++a) {
      dot += m_[a] * raw_[a];
      total += static_cast<std::uint64_t>(raw_[a] * raw_[a]);
    }
    const std::uint64_t along = std::min(static_cast<std::uint64_t>(dot * dot / norm2_), total);
    along_ = along_ - (along_ >> 4) + along;
    across_ = across_ - (across_ >> 4) + (total - along);
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
    for (std::size_t a = 0; a < 3; ++a) {
      m_[a] = static_cast<std::int64_t>(m[a] >> shift);
      norm2_ += m_[a] * m_[a];
    }
  }
  std::uint64_t along_ = 0, across_ = 0;  // running energies: sum of (r.n)^2, of |r|^2 - (r.n)^2
  std::array<std::int64_t, 3> m_{};       // the cell's normal, |m_a| <= 2^15
  std::int64_t norm2_ = 0;                // |m|^2; 0 for a degenerate cell (no chaining)
  std::int64_t a_ = 0, b_ = 1;            // the model's A and B, scaled to at most 2^15 (b_ >= 1)
  std::array<std::int64_t, 3> raw_{};     // this vertex's residuals against the blend, clamped
};

// Encoder statistics of a section coded without chaining: its kind-3 vertices, and how many of them
// the chaining model found anisotropic. The search tries chaining only where that is over a fifth:
// elsewhere it gained at most a few bytes on the shared meshes.
struct ChainCue {
  std::uint32_t vertices = 0, anisotropic = 0;
};

}  // namespace qsp
