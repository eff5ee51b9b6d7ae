// The geometry coder's coding orders and predictor stencils (format-spec/geometry_section.md, "Coding
// orders and stencils"), built from the grid layout of the decoded topology: which vertex is coded at
// each position, and which earlier positions its predictors read. Internal to the geometry coder and
// the codec; tests and tools/spec-check reach it through the private include path.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "qsp/geometry.h"
#include "qsp/partition.h"

namespace qsp {

struct Numbering;  // layout_grid.h

// Per coding position: neighbours coded before it, for geometry prediction (kInvalid if none):
// w = previous along its row/edge, ww = the one before that, s = below, sw = below-left.
// far = for a point inside a schematic edge, the edge's end vertex ahead of it (coded before it), far_dist
// mesh edges away (>= 1); kInvalid and 0 elsewhere. For a patch-inner point (i, j) of an (a,b)-grid:
// e = (a, j) and es = (a, j-1) on the patch side ahead along its row, e_dist = a - i; n = (i, b) and
// nw = (i-1, b) on the side ahead along its column, n_dist = b - j.
// Layout order, across a patch (edge points and schematic vertices): for an edge point, o / ow / ofar =
// the points opposite it, opposite w and opposite far on the patch's other side (ofar may be
// kInvalid). For a schematic vertex, x1 + x2 - x0 (the patch's other three corners) when x2 is set,
// else the lerp x0 + (x1 - x0) * xnum / xden between the two corners of the patch side it lies on.
struct Stencil {
  std::uint32_t w = kInvalid, ww = kInvalid, s = kInvalid, sw = kInvalid;
  std::uint32_t far = kInvalid, far_dist = 0;
  std::uint32_t e = kInvalid, es = kInvalid, n = kInvalid, nw = kInvalid, e_dist = 0, n_dist = 0;
  std::uint32_t o = kInvalid, ow = kInvalid, ofar = kInvalid;
  std::uint32_t x0 = kInvalid, x1 = kInvalid, x2 = kInvalid, xnum = 0, xden = 0;
  // Patch order only: se (1,-1), ss (0,-2), sww (-2,-1), ssw (-1,-2) in w/s's frame, when coded.
  std::uint32_t se = kInvalid, ss = kInvalid, sww = kInvalid, ssw = kInvalid;
  // Mirror prediction (3.17): the vertex's mirror image, when coded before it, and the axis it is
  // reflected along. Set by the codec from the symmetry section, not by the layout.
  std::uint32_t mirror = kInvalid;
  std::uint32_t mirror_axis = 0;
  // Every field that names a vertex (kInvalid when absent): the one list for code that offsets,
  // remaps or checks them all, so a new field cannot be missed in one of those places.
  std::array<std::uint32_t*, 20> vertex_fields() {
    return {&w,  &ww,   &s,  &sw, &far, &e,  &es, &n,   &nw,  &o,
            &ow, &ofar, &x0, &x1, &x2,  &se, &ss, &sww, &ssw, &mirror};
  }
  std::array<std::uint32_t, 20> vertex_fields() const {
    return {w, ww, s, sw, far, e, es, n, nw, o, ow, ofar, x0, x1, x2, se, ss, sww, ssw, mirror};
  }
};

// One component's stencils in coding order `order`, from its grid layout and numbering
// (layout_grid.h). `coding`: the layout vertex at each coding position, for patch order of a schematic
// component; empty where the order is the layout's own (layout order, annulus, torus).
struct ComponentStencils {
  std::vector<Stencil> stencil;
  std::vector<std::uint32_t> coding;
};
ComponentStencils component_stencils(const ComponentPartition& part, const GridLayout& layout,
                                     const Numbering& n, CodingOrder order);

// A whole mesh laid out as the decoder rebuilds it: every component's layout quads offset into one
// vertex numbering, then the unreferenced vertices; with a coding order also the stencils of every
// coding position and, in patch order, `coding` (the layout vertex at each position; identity for
// annulus, torus and unreferenced vertices). Throws Error(kFormat) for a schematic that cannot be laid
// out, Error(kInternal) if patch order misses a vertex.
struct MeshLayout {
  std::uint32_t vertex_count = 0;
  std::vector<std::uint32_t> quads;   // 4 per face, layout numbering
  std::vector<Stencil> stencil;       // per coding position (empty without an order)
  std::vector<std::uint32_t> coding;  // patch order only
};
MeshLayout assemble(std::span<const ComponentPartition> parts, std::uint32_t unreferenced,
                    std::optional<CodingOrder> order);

// The stencils' promise, checked: one per vertex, every field naming an earlier position (a field
// referring forward would read values not decoded yet). Throws Error(kInternal) otherwise.
void check_stencils(std::span<const Stencil> stencil, std::size_t vertex_count);

}  // namespace qsp
