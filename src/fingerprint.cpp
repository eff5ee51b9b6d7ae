// Topology fingerprints of meshes and of .qsp files (qsp/fingerprint.h), on the public codec, match
// and canonical stages.
#include "qsp/fingerprint.h"

#include <utility>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/match.h"
#include "qsp/partition.h"
#include "qsp/regions.h"

// Header-only (XXH_INLINE_ALL): the installed library needs no xxhash to link against.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace qsp {

std::uint64_t mesh_fingerprint(QuadMesh mesh) {
  return topology_fingerprint(prepare_match(std::move(mesh)).canonical);
}

std::uint64_t polygon_fingerprint(const PolygonMatchInput& mesh) {
  const std::uint64_t quads = topology_fingerprint(mesh.quads.canonical);
  const PolygonCounts& n = mesh.counts;
  if (n.triangles == 0 && n.ngons == 0 && n.cut_edges == 0 && n.cut_vertices == 0 && n.extra_copies == 0)
    return quads;  // an all-quad, manifold, oriented mesh: its quad submesh is itself
  const RegionCodes& c = mesh.regions.codes;
  std::vector<std::uint64_t> words = {quads, c.layout_vertices, c.interior_vertices, c.regions.size()};
  for (const RegionCode& r : c.regions) {
    words.insert(words.end(), {static_cast<std::uint64_t>(r.start), r.loop, r.position, r.degrees.size(),
                               r.corners.size(), r.values.size(), r.open.size()});
    words.insert(words.end(), r.degrees.begin(), r.degrees.end());
    for (CornerSymbol s : r.corners) words.push_back(static_cast<std::uint64_t>(s));
    words.insert(words.end(), r.values.begin(), r.values.end());
    words.insert(words.end(), r.open.begin(), r.open.end());
  }
  words.push_back(c.glue_offsets.size());
  words.insert(words.end(), c.glue_offsets.begin(), c.glue_offsets.end());
  words.insert(words.end(), c.glue.begin(), c.glue.end());
  return XXH3_64bits(words.data(), words.size() * sizeof(std::uint64_t));
}

QuadMesh file_connectivity(const FileTopology& topology) {
  QuadMesh mesh;
  std::uint64_t base = 0;
  for (const TopologyCode& code : topology.codes) {
    const GridLayout g = grid_layout(partition_from_code(code));
    if (base + g.vertex_count + topology.unreferenced >= kInvalid)
      throw Error(ErrorCode::kLimit, "the topology describes more than 2^32 - 1 vertices");
    for (std::uint32_t v : g.quads) mesh.quads.push_back(static_cast<std::uint32_t>(base + v));
    base += g.vertex_count;
  }
  if (base + topology.unreferenced >= kInvalid)
    throw Error(ErrorCode::kLimit, "the topology describes more than 2^32 - 1 vertices");
  mesh.positions.assign(3 * (base + topology.unreferenced), 0.0f);
  return mesh;
}

std::uint64_t file_fingerprint(std::string_view qsp_bytes, const DecodeLimits& limits) {
  // The stored codes cannot be hashed as they are: a file may hold a greedy or merged partition
  // (compress keeps the smallest), and the fingerprint is defined on the motorcycle graph.
  return mesh_fingerprint(file_connectivity(file_topology(qsp_bytes, limits)));
}

}  // namespace qsp
