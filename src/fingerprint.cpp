// Topology fingerprints of meshes and of .qsp files (qsp/fingerprint.h), on the public codec, match
// and canonical stages.
#include "qsp/fingerprint.h"

#include <utility>

#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/match.h"
#include "qsp/partition.h"

namespace qsp {

std::uint64_t mesh_fingerprint(QuadMesh mesh) {
  return topology_fingerprint(prepare_match(std::move(mesh)).canonical);
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
