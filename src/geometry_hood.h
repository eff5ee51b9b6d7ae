// A vertex's neighbourhood (format-spec/geometry_section.md, "Neighbourhood"): from the stencils alone,
// its kind (which predictor family applies), its context kind, which of the stencil's optional fields
// count, and the derived neighbours se, ss, sww, ssw. Both sides compute it, so nothing is signalled.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "qsp/geometry.h"
#include "stencil.h"

namespace qsp {

enum Kind : std::uint8_t {
  kNone = 0,
  kWest = 1,
  kLinear = 2,
  kParallelogram = 3,
  kSouth = 4,
  kOpposite = 5,
  kCorners = 6
};

inline constexpr int kContextKinds = 10;  // kinds 0..4, kWest/kLinear with a far end (5, 6), 7, 8, mirrored 9
inline constexpr std::uint8_t kMirrorContext = 9;  // a vertex predicted from its mirror image
inline constexpr int kBlendedContext = 3;          // the context kind of kParallelogram, the blended vertices
inline constexpr std::uint32_t kMaxFarDist = 64;   // farther ends are ignored (and keep the products small)

// A vertex's coded neighbours on its grid, (column, row) offsets from it: w (-1,0), ww (-2,0),
// s (0,-1), sw (-1,-1), and for kParallelogram se (1,-1), ss (0,-2), sww (-2,-1), ssw (-1,-2).
struct Hood {
  std::uint32_t w = kInvalid, ww = kInvalid, s = kInvalid, sw = kInvalid, se = kInvalid, ss = kInvalid,
                sww = kInvalid, ssw = kInvalid;
  const Stencil* t = nullptr;  // its stencil, for the fields `sides` says count
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

// The neighbourhoods of a section's vertices, each computed when the coding loop reaches it (an array
// of them cost 48 bytes a vertex and a pass over memory).
class Hoods {
 public:
  Hoods(std::span<const Stencil> st, CodingOrder order) : st_(st), order_(order) {
    if (order != CodingOrder::kLayout) return;
    // east[x]: the vertex whose w is x and whose s is east of x's s, i.e. x's right neighbour in a grid row.
    east_.assign(st.size(), kInvalid);
    for (std::uint32_t y = 0; y < st.size(); ++y)
      if (full(y)) east_[st[y].w] = y;
  }
  std::uint32_t size() const { return static_cast<std::uint32_t>(st_.size()); }

  Hood operator[](std::uint32_t i) const {
    const Stencil& s = st_[i];
    Hood x;
    // ww and sw only count next to a w (and sw next to an s): a stencil cannot have holes.
    x.w = s.w, x.s = s.s;
    x.ww = s.w != kInvalid ? s.ww : kInvalid;
    x.sw = s.w != kInvalid && s.s != kInvalid ? s.sw : kInvalid;
    if (full(i)) {
      x.kind = kParallelogram;
      if (s.e != kInvalid && s.es != kInvalid && s.e_dist >= 1) x.sides |= Hood::kEast;
      if (s.n != kInvalid && s.nw != kInvalid && s.n_dist >= 1) x.sides |= Hood::kNorth;
      if (order_ == CodingOrder::kPatch) {  // the stencil knows the frame across patch sides
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
      if (s.o != kInvalid && s.ow != kInvalid) {
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
  std::span<const Stencil> st_;
  CodingOrder order_;
  std::vector<std::uint32_t> east_;  // layout order only
};

}  // namespace qsp
