// The layout numbering of a schematic component (format-spec/qsp_format.md, "Grid layout"), shared by
// grid_layout (src/layout.cpp) and the geometry coder's stencils (src/stencil.cpp). Internal.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "qsp/partition.h"

namespace qsp {

// Grid points of one patch in layout numbering: P(i, j), 0 <= i <= a, 0 <= j <= b.
struct PatchGrid {
  std::uint32_t a = 0, b = 0;
  std::span<const std::uint32_t> ring;  // boundary points counter-clockwise from corner (0,0)
  std::uint32_t interior_base = 0;      // first id of the (a-1)(b-1) inner points, row by row
  std::uint32_t at(std::uint32_t i, std::uint32_t j) const {
    if (j == 0) return ring[i];
    if (i == a) return ring[a + j];
    if (j == b) return ring[2 * a + b - i];
    if (i == 0) return ring[2 * a + 2 * b - j];
    return interior_base + (j - 1) * (a - 1) + (i - 1);
  }
  // Row j's points, at(0, j) .. at(a, j), into out[0 .. a].
  void row(std::uint32_t j, std::uint32_t* out) const {
    const std::uint32_t w = a, h = b;  // locals: a store to out might otherwise change them
    const std::uint32_t* const r = ring.data();
    if (j == 0) {
      std::copy(r, r + w + 1, out);
    } else if (j == h) {
      for (std::uint32_t i = 0; i <= w; ++i) out[i] = r[2 * w + h - i];
    } else {
      out[0] = r[2 * w + 2 * h - j];
      const std::uint32_t first = interior_base + (j - 1) * (w - 1) - 1;
      for (std::uint32_t i = 1; i < w; ++i) out[i] = first + i;
      out[w] = r[w + j];
    }
  }
};

// Numbering of a general schematic's vertices: X, then edge-inner, then patch-inner points.
// The patches' rings lie in one array (one allocation, not one per patch), so a copy would point
// into the original's: it moves only.
struct Numbering {
  std::vector<std::uint32_t> edge_base;  // per edge: id of its first inner point
  std::vector<PatchGrid> patches;        // per face (empty for holes)
  std::vector<std::uint32_t> rings;      // the patches' rings, one after another
  std::uint32_t vertex_count = 0;

  Numbering() = default;
  Numbering(Numbering&&) = default;
  Numbering& operator=(Numbering&&) = default;
};

// Numbers a schematic's vertices into `n`. Returns an empty string, or why the schematic cannot be laid
// out (unequal opposite sides, too many vertices).
std::string number_schematic(const Schematic& s, Numbering& n);

// The mesh under each patch of a general component, walked from its face_dart corner as link walks
// it: it depends on the patches, not on the dart labels, so canonicalize computes it on the second core
// while it chooses the root. Flat, per face (holes: empty).
struct PatchWalks {
  std::vector<std::uint32_t> a, b;                   // per face: the grid's sizes
  std::vector<std::size_t> cell_begin, point_begin;  // per face: where its cells and points start
  std::vector<std::uint32_t> cell;                   // per cell, row by row: the mesh half-edge at its bottom
  std::vector<std::uint32_t> point;  // per grid point, (a + 1) a row, row by row: its mesh vertex
  bool ok = false;  // false: some walk leaves the component, clashes or does not fit; link decides
};
PatchWalks walk_patches(const ComponentPartition& part, const Adjacency& adj) noexcept;

// layout_to_mesh's map of `relabelled`, whose dart i is dart order[i] of `original`, from the walks
// of `original`: true when it holds; false (map undefined) where layout_to_mesh is to decide.
bool link_from_walks(const ComponentPartition& relabelled, const Schematic& original,
                     std::span<const std::uint32_t> order, const PatchWalks& walks, LayoutMap& map);

// grid_layout, also handing back the numbering of a schematic component (left empty for an annulus or
// torus), for the stencils.
GridLayout grid_layout(const ComponentPartition& part, Numbering& numbering);

}  // namespace qsp
