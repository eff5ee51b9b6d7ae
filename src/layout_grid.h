// The layout numbering of a schematic component (format-spec/qsp_format.md, "Grid layout"), shared by
// grid_layout (src/layout.cpp) and the geometry coder's stencils (src/stencil.cpp). Internal.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "qsp/partition.h"

namespace qsp {

// Grid points of one patch in layout numbering: P(i, j), 0 <= i <= a, 0 <= j <= b.
struct PatchGrid {
  std::uint32_t a = 0, b = 0;
  std::vector<std::uint32_t> ring;  // boundary points counter-clockwise from corner (0,0)
  std::uint32_t interior_base = 0;  // first id of the (a-1)(b-1) inner points, row by row
  std::uint32_t at(std::uint32_t i, std::uint32_t j) const {
    if (j == 0) return ring[i];
    if (i == a) return ring[a + j];
    if (j == b) return ring[2 * a + b - i];
    if (i == 0) return ring[2 * a + 2 * b - j];
    return interior_base + (j - 1) * (a - 1) + (i - 1);
  }
};

// Numbering of a general schematic's vertices: X, then edge-inner, then patch-inner points.
struct Numbering {
  std::vector<std::uint32_t> edge_base;  // per edge: id of its first inner point
  std::vector<PatchGrid> patches;        // per face (empty for holes)
  std::uint32_t vertex_count = 0;
};

// Numbers a schematic's vertices into `n`. Returns an empty string, or why the schematic cannot be laid
// out (unequal opposite sides, too many vertices).
std::string number_schematic(const Schematic& s, Numbering& n);

// grid_layout, also handing back the numbering of a schematic component (left empty for an annulus or
// torus), for the stencils.
GridLayout grid_layout(const ComponentPartition& part, Numbering& numbering);

}  // namespace qsp
