// qsp/smaller.h: structured partitions smaller than the motorcycle graph (paper §7).
//
// Three modes, all giving partitions that partition_from_cuts has validated (every patch an (a,b)-grid,
// exact tiling) so any of them decodes with the same decoder:
//   kMotorcycle  the motorcycle graph of §5 (partition_motorcycle).
//   kGreedy      §7's path-at-a-time construction from the extraordinary vertices, then the merge pass.
//   kMerge       the motorcycle graph, then repeated merging of two patches whose union is a grid.
// All three are canonical: every choice is ordered by structure and then by the canonical dart labels
// of a canonical schematic, so isomorphic meshes get isomorphic partitions (equal TopologyCodes). On a
// mesh with symmetries several labellings are canonical; given the positions, greedy and merge take
// the one the codec would (smallest positions), so a renumbered copy gets the same partition, not just
// an isomorphic one, and the same .qsp bytes.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "qsp/mesh.h"
#include "qsp/partition.h"

namespace qsp {

enum class PartitionMode : std::uint8_t { kMotorcycle = 0, kGreedy = 1, kMerge = 2 };

// "motorcycle", "greedy", "merge".
const char* partition_mode_name(PartitionMode mode) noexcept;
// Parses one of the names above into `out`; returns false (out untouched) for anything else.
bool parse_partition_mode(std::string_view name, PartitionMode& out) noexcept;

// The partition of every component of `adj` (a valid Adjacency from build_adjacency) in `mode`.
// Structured components (disk, annulus, torus) come out exactly as partition_motorcycle makes them.
// Never returns an invalid partition: a heuristic whose cut set fails partition_from_cuts' checks
// falls back to the motorcycle graph for the whole mesh. Throws Error(kInternal) only where
// partition_motorcycle itself would. Deterministic; depends only on connectivity and orientation
// (isomorphic meshes give isomorphic partitions) and, among symmetric choices, on `positions` (3
// floats per vertex; empty: the choice follows the numbering). Safe on any mesh build_adjacency
// accepted.
Partition partition(const Adjacency& adj, PartitionMode mode, std::span<const float> positions = {});

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
