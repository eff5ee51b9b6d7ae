// Predictors (format-spec/geometry_section.md, "Predictors"): the candidates of a full cell and their
// blend, weighted by each one's recent errors; the shape transfers of the cell shapes tool; the fixed
// predictors of the other kinds; the float-bits predictors. Everything here depends only on values
// already coded and on the stencils, so both sides agree without signalling.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "geometry_hood.h"
#include "geometry_values.h"

namespace qsp {

// Integer predictors. Blending them helps most where a coarse mesh bends (spot, blub): the
// parallelogram alone misses curvature, the quadratic ones overshoot on noise.
inline constexpr int kCandidates = 14;      // with the cell shapes tool
inline constexpr int kBaseCandidates = 11;  // without it
inline constexpr std::uint32_t kNoError = 0xFFFFFFFFu;

// Which candidates vertex hood x has all neighbours for (bit k = candidate k): with the cell shapes
// tool also the shrunk parallelogram (11, with the parallelogram's neighbours) and the shape transfers
// from the west cell (12, with candidate 4's) and the south cell (13, with candidate 5's) when every
// axis is an integer axis; shape_transfers() may still take 12 and 13 away.
inline unsigned candidate_mask(const Hood& x, bool shapes, bool integer_axes) {
  const bool w = x.w != kInvalid, ww = x.ww != kInvalid, s = x.s != kInvalid, sw = x.sw != kInvalid;
  const bool full = x.kind == kParallelogram;
  const bool se = x.se != kInvalid, ss = x.ss != kInvalid, sww = x.sww != kInvalid, ssw = x.ssw != kInvalid;
  const unsigned m = (w && s && sw) << 0 | (w && ww) << 1 | (w && ww && s && sw && se) << 2 | (s && ss) << 3 |
                     (w && ww && s && sw && sww) << 4 | (w && s && sw && ss && ssw) << 5 | w << 6 |
                     (w && se && sw) << 7 | (full && x.has(Hood::kEast)) << 8 |
                     (full && x.has(Hood::kNorth)) << 9 |
                     (full && x.has(Hood::kEast) && x.has(Hood::kNorth)) << 10;
  if (!shapes) return m;
  return m | (m & 1u) << 11 | (integer_axes ? ((m >> 4) & 1u) << 12 | ((m >> 5) & 1u) << 13 : 0u);
}

// How the column step s - sw... at the row's end differs from w's, spread over the e_dist + 1 steps.
inline std::int64_t row_correction(const Hood& x, const std::int64_t* v) {
  const std::int64_t d = std::int64_t{x.t->e_dist} + 1, c = (v[x.t->e] - v[x.t->es]) - (v[x.w] - v[x.sw]);
  return floor_div(2 * c + d, 2 * d);
}
inline std::int64_t column_correction(const Hood& x, const std::int64_t* v) {
  const std::int64_t d = std::int64_t{x.t->n_dist} + 1, c = (v[x.t->n] - v[x.t->nw]) - (v[x.s] - v[x.sw]);
  return floor_div(2 * c + d, 2 * d);
}

// The candidates 0-11 of vertex hood x on one axis (values v) into p[k], for every k in mask. Absent
// neighbours read as 0, so the eight cheap candidates are one straight block sharing their loads (a
// switch per candidate cost an eighth of the encoder); p[k] for k not in mask is never used.
inline void candidates(const Hood& x, const std::int64_t* v, unsigned mask,
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
  // Cell shapes: the parallelogram shrunk towards sw, for the distorted cells near extraordinary
  // vertices (12 and 13, the shape transfers, come from shape_transfers()).
  if ((mask >> 11) & 1) p[11] = sw + ((13 * (w + s - 2 * sw) + 8) >> 4);
}

// floor(sqrt(n)), exactly.
inline std::uint64_t isqrt(std::uint64_t n) {
  auto r = static_cast<std::uint64_t>(std::sqrt(static_cast<double>(n)));
  while (r > 0 && (r > 0xFFFFFFFFu || r * r > n)) --r;
  while (r < 0xFFFFFFFFu && (r + 1) * (r + 1) <= n) ++r;
  return r;
}

using Vec3 = std::array<std::int64_t, 3>;

// Similarity shape transfer: a fully coded neighbour cell with corner o2, edges e2 (its row step) and
// f2 (its column step) and opposite corner o2 + d2. Its shape, d2 in the frame of e2 and e2 turned a
// right angle in its plane (the part along its normal dropped), is carried into the frame of the cell
// being coded (corner o, edges e, f), whose opposite corner is predicted. False (no prediction) for a
// degenerate cell or a component of 2^15 or more. Integer only; spec, "Shape transfers".
inline bool transfer(const Vec3& o, const Vec3& e, const Vec3& f, const Vec3& e2, const Vec3& f2,
                     const Vec3& d2, Vec3& out) {
  constexpr std::int64_t kLimit = std::int64_t{1} << 15;
  for (std::size_t a = 0; a < 3; ++a)
    for (std::int64_t c : {e[a], f[a], e2[a], f2[a], d2[a]})
      if (c <= -kLimit || c >= kLimit) return false;
  auto dot = [](const Vec3& p, const Vec3& q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; };
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
  for (std::size_t a = 0; a < 3; ++a) {
    const __int128 num = __int128{pd} * e[a] * s + q * (__int128{ee} * f[a] - __int128{ef} * e[a]);
    out[a] = o[a] + static_cast<std::int64_t>(floor_div128(2 * num + den, 2 * den));
  }
  return true;
}

// The shape transfers at vertex hood x (mask: its candidates) into shape[0] (the west cell's,
// candidate 12) and shape[1] (the south cell's, 13), from the integer axes `v`. Returns the mask bits of
// those with no prediction.
inline unsigned shape_transfers(const Hood& x, const std::array<std::vector<std::int64_t>, 3>& v,
                                unsigned mask, std::array<Vec3, 2>& shape) {
  auto at = [&v](std::uint32_t j) { return Vec3{v[0][j], v[1][j], v[2][j]}; };
  auto sub = [](const Vec3& p, const Vec3& q) { return Vec3{p[0] - q[0], p[1] - q[1], p[2] - q[2]}; };
  const Vec3 w = at(x.w), s = at(x.s), sw = at(x.sw);
  const Vec3 e = sub(s, sw), f = sub(w, sw);
  // The similarity that keeps the row step's shape and the one that keeps the column step's, averaged.
  auto similar = [&](const Vec3& e2, const Vec3& f2, const Vec3& d2, Vec3& out) {
    Vec3 p, q;
    if (!transfer(sw, e, f, e2, f2, d2, p) || !transfer(sw, f, e, f2, e2, d2, q)) return false;
    for (std::size_t a = 0; a < 3; ++a) out[a] = (p[a] + q[a] + 1) >> 1;
    return true;
  };
  unsigned off = 0;
  if ((mask >> 12) & 1) {  // the west cell: sww, sw (its row step), ww (its column step), w
    const Vec3 sww = at(x.sww);
    if (!similar(sub(sw, sww), sub(at(x.ww), sww), sub(w, sww), shape[0])) off |= 1u << 12;
  }
  if ((mask >> 13) & 1) {  // the south cell: ssw, ss (its row step), sw (its column step), s
    const Vec3 ssw = at(x.ssw);
    if (!similar(sub(at(x.ss), ssw), sub(sw, ssw), sub(s, ssw), shape[1])) off |= 1u << 13;
  }
  return off;
}

// Weights of the candidates at a parallelogram vertex: the inverse square of each one's mean error
// at the coded neighbours w, s, sw, se (integer axes summed). 0 for a missing candidate. <= 2^30.
// Returns the blend class: bit_width of the best candidate's floor(4 * mean + 2). nc: the section's
// candidate count (a constant, so sections without the cell shapes tool run as fast as before it).
template <int nc>
int blend_weights(const Hood& x, unsigned mask, const std::uint32_t* errors,
                  std::array<std::int64_t, kCandidates>& weight) {
  // w, s and sw are there at every parallelogram vertex (Hoods gives the kind only then); a missing se
  // reads a row of kNoError. So each candidate sums four loads without a branch per neighbour.
  static constexpr std::array<std::uint32_t, kCandidates> kNone = [] {
    std::array<std::uint32_t, kCandidates> r{};
    r.fill(kNoError);
    return r;
  }();
  const std::uint32_t* const e0 = errors + std::size_t{x.w} * nc;
  const std::uint32_t* const e1 = errors + std::size_t{x.s} * nc;
  const std::uint32_t* const e2 = errors + std::size_t{x.sw} * nc;
  const std::uint32_t* const e3 = x.se != kInvalid ? errors + std::size_t{x.se} * nc : kNone.data();
  std::uint64_t best = ~std::uint64_t{0};
  for (int k = 0; k < nc; ++k) {
    if (!((mask >> k) & 1)) continue;
    std::uint64_t sum = 0, cnt = 0;
    for (const std::uint32_t e : {e0[k], e1[k], e2[k], e3[k]}) {
      const bool known = e != kNoError;
      sum += known ? e : 0;
      cnt += known;
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
    weight[static_cast<std::size_t>(k)] = w * w;
    const std::uint64_t mean4 = cnt == 1 ? 4 * sum : cnt == 2 ? 2 * sum : cnt == 4 ? sum : 4 * sum / 3;
    best = std::min(best, mean4 + 2);
  }
  return std::bit_width(best);
}

// The weighted mean of the available candidates p[k] (mask bit k), as an offset from the
// parallelogram p[0] (clamped to +-2^28 so the sums cannot overflow), rounded half up. Integer only,
// so exactly reproducible.
// kClamp false: the caller knows every |p[k] - p[0]| <= 2^28 (blend_unclamped), so the clamps are no-ops.
template <int nc, bool kClamp = true>  // nc as for blend_weights
std::int64_t blend(const std::array<std::int64_t, kCandidates>& p, unsigned mask,
                   const std::array<std::int64_t, kCandidates>& weight) {
  std::int64_t num = 0, den = 0;
  for (int k = 0; k < nc; ++k) {
    if (!((mask >> k) & 1)) continue;
    const std::int64_t d = p[static_cast<std::size_t>(k)] - p[0];
    num +=
        weight[static_cast<std::size_t>(k)] * (kClamp ? std::clamp<std::int64_t>(d, -(1 << 28), 1 << 28) : d);
    den += weight[static_cast<std::size_t>(k)];
  }
  return den == 0 ? p[0] : p[0] + floor_div(2 * num + den, 2 * den);
}

// Whether blend's clamps cannot bind: without the shape transfers (which can reach far), candidates
// 0-10 of grid values in [0, q] lie in [-8q, 8q] and the parallelogram in [-q, 2q], so every offset
// is within 10q < 2^28 for q < 2^24.
inline bool blend_unclamped(bool shapes, std::uint32_t bits) { return !shapes && bits != 0 && bits <= 20; }

// The fixed predictor of kinds other than kParallelogram on an integer axis (values v), and the
// across-patch predictions of kOpposite and kCorners.
inline std::int64_t predict_kind(const Hood& x, Kind kind, const std::int64_t* v) {
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
      const Stencil& t = *x.t;
      if (x.has(Hood::kOppositeFar)) {  // the offset to the side across, interpolated between w and far
        const std::int64_t d = t.far_dist;
        return v[t.o] + floor_div(2 * (d * (v[x.w] - v[t.ow]) + (v[t.far] - v[t.ofar])) + d + 1, 2 * (d + 1));
      }
      return v[x.w] + v[t.o] - v[t.ow];
    }
    case kCorners: {
      const Stencil& t = *x.t;
      if (t.x2 != kInvalid) return v[t.x1] + v[t.x2] - v[t.x0];
      const __int128 num = static_cast<__int128>(v[t.x1] - v[t.x0]) * t.xnum;
      return v[t.x0] + static_cast<std::int64_t>(floor_div128(2 * num + t.xden, 2 * __int128{t.xden}));
    }
  }
  return 0;
}

// Float-axis prediction (an image): additions in binary64 (no products, so no FMA contraction can
// change it), rounded once to binary32; if that is not finite (a NaN/inf operand or overflow), w's own bits.
inline std::uint32_t predict_float(const Hood& x, Kind kind, const float* f) {
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

}  // namespace qsp
