// qsp/smaller.h: structured partitions smaller than the motorcycle graph (paper §7): the greedy
// construction and the merge pass behind PartitionMode::kGreedy and kMerge (qsp/partition.h).
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "qsp/mesh.h"
#include "qsp/partition.h"

namespace qsp {

// The greedy construction alone (no merge pass): the cut half-edges, one per cut edge, boundary edges
// not included. Every extraordinary vertex is left with no two consecutive uncut edges and no region
// is an annulus, so partition_from_cuts accepts the result (tests check this on every mesh).
std::vector<std::uint32_t> greedy_cuts(const Adjacency& adj, std::span<const float> positions = {});

// The merge pass: partitions along `cuts` (any cut set partition_from_cuts accepts), then repeatedly
// merges two patches that share one full side whose ends are corners of both and touch nowhere else,
// working on the schematic alone. Returns the reduced cut set (a subset of `cuts`, one half-edge per
// edge). Throws Error(kInternal) if `cuts` itself is not a valid partition.
std::vector<std::uint32_t> merge_cuts(const Adjacency& adj, std::span<const std::uint32_t> cuts,
                                      std::span<const float> positions = {});

// Schematic size of a partition summed over components: vertices, edges and patches (an annulus or
// torus component counts as one patch with no vertices or edges), as in `qsp stats`.
struct PartitionSize {
  std::uint64_t vertices = 0, edges = 0, patches = 0;
};
PartitionSize partition_size(const Partition& p);

}  // namespace qsp
