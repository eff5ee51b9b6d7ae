// What a partition amounts to, for hand-checked cases: schematic vertices, edges, patches and holes,
// the patch sizes, the component kinds.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "qsp/partition.h"

namespace qsp::testing {

struct SchematicCounts {
  std::uint32_t x = 0, e = 0, patches = 0, holes = 0;          // an annulus or torus counts as one patch
  std::vector<std::pair<std::uint32_t, std::uint32_t>> sizes;  // per patch (min, max) side, sorted
  std::vector<ComponentKind> kinds;                            // per component, in partition order
};

inline SchematicCounts schematic_counts(const Partition& p) {
  SchematicCounts c;
  for (const auto& part : p.components) {
    c.kinds.push_back(part.kind);
    if (part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus) {
      ++c.patches;
      continue;
    }
    const Schematic& s = part.schematic;
    c.x += s.vertex_count;
    c.e += s.edge_count();
    c.patches += s.patch_count();
    c.holes += s.face_count() - s.patch_count();
    for (std::uint32_t f = 0; f < s.face_count(); ++f)
      if (!s.face_hole[f]) {
        const PatchSize z = patch_size(s, f);
        c.sizes.emplace_back(std::min(z.a, z.b), std::max(z.a, z.b));
      }
  }
  std::sort(c.sizes.begin(), c.sizes.end());
  return c;
}

}  // namespace qsp::testing
