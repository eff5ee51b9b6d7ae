// The coding loop the geometry encoder and decoder share (format-spec/geometry_section.md, "Decoding a
// vertex"), so the two cannot drift apart: per vertex its neighbourhood, candidates and blend, per axis
// its contexts and prediction, then the coordinate itself, which is where encoding and decoding differ.
// That part is the policy `Io` (GeometryEncoder in geometry_encoder.cpp, GeometryDecoder in
// geometry_decoder.cpp):
//
//   Coded code(const Coordinate& c);   the coordinate's residual or repeat, leaving its value in
//                                      values.ints / values.floats and returning u and whether it repeated
//   ChainCue* cue();                   the encoder's chaining statistics, or null
//
// kShapes and kLogistic are the cell shapes and logistic mixing tools, template arguments so that a
// section without them runs as fast as if they did not exist (a branch in the loop cost a large decode
// 3% of its instructions).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry_chain.h"
#include "geometry_header.h"
#include "geometry_hood.h"
#include "geometry_model.h"
#include "geometry_predict.h"

namespace qsp {

// Every axis's values: integers on integer axes, floats on float-bits axes.
struct Values {
  std::array<std::vector<std::int64_t>, 3> ints;
  std::array<std::vector<float>, 3> floats;
};

// One coordinate, as the loop hands it to the policy.
struct Coordinate {
  std::uint32_t vertex = 0;
  int axis = 0;
  std::int64_t pred = 0;    // the clamped prediction p (float-bits axes: an image)
  ResidualContext context;  // the residual's contexts
  int previous = 0;         // value repeats: how the vertex's previous axis went (0 x, 1 residual, 2 repeat)
  const Exception* exception;  // a decimal exception at this coordinate (no repeat; coded as p), or null
};

struct Coded {
  std::uint64_t u;  // the residual's zigzag value (for a repeat: what it would have been, t ignored)
  bool repeat;
};

// The magnitude class of axis a with logistic mixing, for full cells: the bit width of twice the
// weighted mean of the coded values u of the neighbours on the axis (w and s weigh 2, sw and se 1) and
// of the vertex's earlier axes (2 each), as the neighbour class in `neighbour`; returned mixed 3:1 with
// the blend's class. Residual magnitudes follow the local distortion more closely than lengths do.
inline int magnitude_class(const std::array<std::vector<std::uint32_t>, 3>& mags, const Hood& x,
                           std::uint32_t i, int a, int blend_class, int& neighbour) {
  const std::uint32_t* m = mags[static_cast<std::size_t>(a)].data();
  std::uint64_t sum = 2 * (std::uint64_t{m[x.w]} + m[x.s]) + m[x.sw], weight = 5;
  if (x.se != kInvalid) sum += m[x.se], ++weight;
  for (std::size_t b = 0; b < static_cast<std::size_t>(a); ++b)
    sum += 2 * std::uint64_t{mags[b][i]}, weight += 2;
  const int cls = static_cast<int>(std::bit_width(2 * sum / weight));
  neighbour = std::min(kClasses - 1, cls);
  return std::min(kClasses - 1, (3 * cls + blend_class + 2) >> 2);
}

// The magnitude class from the neighbours' residual lengths: the mean of w's and s's.
inline int length_class(const std::uint8_t* lengths, const Hood& x) {
  int v = 0;
  if (x.w != kInvalid && x.s != kInvalid) {
    v = (lengths[x.w] + lengths[x.s] + 1) >> 1;
  } else if (x.w != kInvalid) {
    v = lengths[x.w];
  } else if (x.s != kInvalid) {
    v = lengths[x.s];
  }
  return std::min(v, kClasses - 1);
}

// Codes the first `count` vertices (stencils only look back, so a prefix codes on its own).
template <class Io, bool kShapes, bool kLogistic>
void code_vertices(const Header& h, const Hoods& hoods, std::uint32_t count, Values& values, Io& io) {
  auto& ints = values.ints;
  auto& floats = values.floats;
  const bool any_int = h.any_integer_axis(), all_int = h.integer_axes(),
             repeats = h.has(geometry_tool::kValueRepeats);
  constexpr int nc = kShapes ? kCandidates : kBaseCandidates;
  // The header's answers in locals: the loop's byte stores could alias it, so each use reloaded it.
  const std::array<bool, 3> int_axis = {h.integer_axis(0), h.integer_axis(1), h.integer_axis(2)};
  const std::array<int, 3> max_length = {h.max_length(0), h.max_length(1), h.max_length(2)};
  const bool quantized = h.bits != 0, unclamped = blend_unclamped(kShapes, h.bits);
  // [vertex][candidate]: each vertex's row is written whole once it is coded, and only later vertices
  // read it, so it needs no filling first (which cost a pass over 44 bytes a vertex).
  const auto errors = std::make_unique_for_overwrite<std::uint32_t[]>(any_int ? std::size_t{count} * nc : 0);
  std::array<std::vector<std::uint8_t>, 3> lengths;  // per axis: each coded L
  for (auto& l : lengths) l.assign(count, 0);
  std::array<std::vector<std::uint32_t>, 3> mags;  // logistic mixing: each coded u, at most 2^32 - 1
  if constexpr (kLogistic)
    for (auto& m : mags) m.assign(count, 0);
  std::array<Vec3, 2> shape{};  // the two transfers' predictions
  std::array<std::size_t, 3> next_exception{};
  const std::int64_t qmax = h.bits ? static_cast<std::int64_t>((std::uint64_t{1} << h.bits) - 1) : 0;
  std::array<std::int64_t, kCandidates> weight{};
  std::array<std::array<std::int64_t, kCandidates>, 3> cand{};
  // Across-patch vertices: running means (x16) of the errors of the across prediction [0] and of the
  // prediction along the vertex's own edge [1], per class; the one with the smaller mean is used.
  // (Blending the two was worse: on CAD-like meshes the across prediction is often exact.)
  std::array<std::array<std::uint64_t, 2>, 4> across_err{};
  std::array<std::array<std::int64_t, 2>, 3> across_pred{};
  // Mirror prediction: per mirror axis, per axis, the last mirrored vertex's value less its image's
  // (reflected on the mirror axis): the plane's offset, learnt as the vertices come.
  const bool mirroring = h.has(geometry_tool::kMirror);
  std::array<std::array<std::int64_t, 3>, 3> mirror_offset{};
  NormalChain chain;
  const bool chaining = h.has(geometry_tool::kNormalChaining) && all_int;
  // The chaining model runs (its offsets only if chaining) for the decoder and for the encoder's cue.
  ChainCue* const cue = io.cue();
  const bool modelled = all_int && (chaining || cue);
  for (std::uint32_t i = 0; i < count; ++i) {
    int previous = 0;  // how the vertex's previous axis was coded: 0 none / no repeats, 1 residual, 2 repeat
    const Hood x = hoods[i];
    const std::uint32_t image = mirroring ? x.t->mirror : kInvalid;
    const auto maxis = static_cast<std::size_t>(x.t->mirror_axis);
    unsigned mask = any_int ? candidate_mask(x, kShapes, all_int) : 0;
    if constexpr (kShapes) {
      if (mask >> 12) mask &= ~shape_transfers(x, ints, mask, shape);
    }
    const bool blended = any_int && x.kind == kParallelogram && image == kInvalid;
    const int blend_class = blended ? blend_weights<nc>(x, mask, errors.get(), weight) : 0;
    const bool across = (x.kind == kOpposite || x.kind == kCorners) && image == kInvalid;
    // Its across class: which running means it uses.
    const std::size_t cls = !across               ? 0
                            : x.kind == kOpposite ? (x.has(Hood::kOppositeFar) ? 0 : 1)
                                                  : (x.t->x2 != kInvalid ? 2 : 3);
    for (std::size_t a = 0; a < 3; ++a) {
      if (!int_axis[a]) continue;
      candidates(x, ints[a].data(), mask, cand[a]);
      if constexpr (kShapes) cand[a][12] = shape[0][a], cand[a][13] = shape[1][a];
    }
    const bool chained = modelled && blended;
    if (chained) {
      chain.start(x, ints);
      if (cue) ++cue->vertices, cue->anisotropic += chain.anisotropic();
    }
    std::array<std::int64_t, 3> blended_pred{};
    for (int a = 0; a < 3; ++a) {
      const auto ua = static_cast<std::size_t>(a);
      const std::uint8_t ctx = image != kInvalid ? kMirrorContext : x.ctx;
      Coordinate c{i, a, 0, {ctx, 0, max_length[ua], a, 0, 0}, previous, nullptr};
      // Magnitude class: neighbours' residual lengths, averaged with the blend's expected error.
      int cls_l = length_class(lengths[ua].data(), x), neighbour = cls_l;
      if (blended) {
        cls_l = kLogistic ? magnitude_class(mags, x, i, a, blend_class, neighbour)
                          : std::min(kClasses - 1, (cls_l + blend_class + 1) >> 1);
      }
      c.context.cls = cls_l;
      if constexpr (kLogistic) {
        c.context.neighbour_cls = neighbour;
        c.context.previous = a == 0 ? 0 : std::min<int>(kClasses - 1, lengths[ua - 1][i]);
      }
      if (int_axis[ua]) {
        const std::int64_t* v = ints[ua].data();
        std::int64_t pred;
        if (image != kInvalid) {
          pred = (ua == maxis ? -v[image] : v[image]) + mirror_offset[maxis][ua];
        } else if (blended) {
          pred = blended_pred[ua] =
              unclamped ? blend<nc, false>(cand[ua], mask, weight) : blend<nc>(cand[ua], mask, weight);
          if (chaining) pred += chain.offset(a);
        } else if (across) {
          const std::int64_t pa = predict_kind(x, x.kind, v), pf = predict_kind(x, x.fallback, v);
          across_pred[ua] = {pa, pf};
          pred = across_err[cls][0] <= across_err[cls][1] ? pa : pf;
        } else {
          pred = predict_kind(x, x.kind, v);
        }
        if (quantized) {
          c.pred = std::clamp<std::int64_t>(pred, 0, qmax);
        } else {
          c.pred = clamp_decimal(pred);
          const std::vector<Exception>& ex = h.plans[ua].exceptions;
          std::size_t& e = next_exception[ua];
          if (e < ex.size() && ex[e].vertex == i) c.exception = &ex[e++];
        }
      } else {
        const float* f = floats[ua].data();
        c.pred = predict_float(x, x.kind, f);
        if (across) {
          const std::int64_t pf = predict_float(x, x.fallback, f);
          across_pred[ua] = {c.pred, pf};
          if (across_err[cls][0] > across_err[cls][1]) c.pred = pf;
        }
      }
      const Coded coded = io.code(c);
      lengths[ua][i] = static_cast<std::uint8_t>(std::bit_width(coded.u));
      if constexpr (kLogistic)
        mags[ua][i] = static_cast<std::uint32_t>(std::min<std::uint64_t>(coded.u, 0xFFFFFFFFu));
      if (chained) {
        const std::int64_t r = ints[ua][i] - blended_pred[ua];
        chain.record(a, quantized ? wrapped(r, qmax) : r);
      }
      if (repeats) previous = coded.repeat ? 2 : 1;
    }
    if (across) {
      for (std::size_t p = 0; p < 2; ++p) {
        std::uint64_t err = 0;
        for (std::size_t a = 0; a < 3; ++a) {
          const bool is_int = int_axis[a];
          if (any_int && !is_int) continue;
          const std::int64_t value =
              is_int ? ints[a][i] : static_cast<std::int64_t>(float_image(floats[a][i]));
          err += static_cast<std::uint64_t>(
              std::min<std::int64_t>(std::abs(value - across_pred[a][p]), kNoError));
        }
        across_err[cls][p] += err - (across_err[cls][p] >> 4);
      }
    }
    if (chained) chain.finish();
    if (image != kInvalid)
      for (std::size_t a = 0; a < 3; ++a)
        mirror_offset[maxis][a] = ints[a][i] - (a == maxis ? -ints[a][image] : ints[a][image]);
    if (!any_int) continue;
    // The vertex's values in locals, and the axes tested once: the stores to the row may alias both.
    std::array<std::int64_t, 3> value{};
    for (std::size_t a = 0; a < 3; ++a)
      if (int_axis[a]) value[a] = ints[a][i];
    std::uint32_t* const row = errors.get() + std::size_t{i} * nc;
    for (int k = 0; k < nc; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      if (!((mask >> k) & 1)) {
        row[uk] = kNoError;
        continue;
      }
      // A float axis adds |0 - 0|: its value and candidates stay 0 (no test per axis and candidate).
      std::uint64_t err = 0;
      for (std::size_t a = 0; a < 3; ++a)
        err += static_cast<std::uint64_t>(std::min<std::int64_t>(std::abs(value[a] - cand[a][uk]), kNoError));
      row[uk] = static_cast<std::uint32_t>(std::min<std::uint64_t>(err, kNoError - 1));
    }
  }
}

// The loop for h's tools.
template <class Io>
void code_section(const Header& h, const Hoods& hoods, std::uint32_t count, Values& values, Io& io) {
  const bool shapes = h.has(geometry_tool::kCellShapes), logistic = h.has(geometry_tool::kLogisticMixing);
  if (shapes && logistic) return code_vertices<Io, true, true>(h, hoods, count, values, io);
  if (shapes) return code_vertices<Io, true, false>(h, hoods, count, values, io);
  if (logistic) return code_vertices<Io, false, true>(h, hoods, count, values, io);
  code_vertices<Io, false, false>(h, hoods, count, values, io);
}

}  // namespace qsp
