// qsp/fingerprint.h: the topology fingerprint of a mesh or of a .qsp file (what `qsp fingerprint`
// prints): equal exactly when the meshes are isomorphic with orientation, up to hash collisions.
#pragma once

#include <cstdint>
#include <string_view>

#include "qsp/codec.h"
#include "qsp/match.h"
#include "qsp/mesh.h"

namespace qsp {

// topology_fingerprint (canonical.h) of `mesh`'s canonical motorcycle-graph form: equal for two meshes
// exactly when they are isomorphic with orientation, whatever their numbering (different topologies
// collide with probability about 2^-64). A scrambled numbering is walked in a local one first
// (prepare_match, match.h). Throws what build_adjacency throws for an invalid mesh. Pass by std::move to
// avoid a copy.
std::uint64_t mesh_fingerprint(QuadMesh mesh);

// The fingerprint of a polygon mesh (prepare_polygon_match, match.h): equal for two polygon meshes
// exactly when they are isomorphic with orientation (a face to a face of its degree, corners in cyclic
// order), up to hash collisions and, where `mesh.capped`, to the ties regions.h names. It hashes the
// quad submesh's canonical codes (as topology_fingerprint), then the region codes, then the glue; an
// all-quad, manifold, oriented mesh gets exactly mesh_fingerprint's value. Never throws.
std::uint64_t polygon_fingerprint(const PolygonMatchInput& mesh);

// The fingerprint of the mesh a .qsp holds: mesh_fingerprint of the mesh it was compressed from,
// whichever partition the file stores (a greedy or merged one is canonicalized again on the
// motorcycle graph), without decoding its positions. Throws as file_topology() does (kFormat, kVersion,
// kChecksum, kLimit past `limits`). Safe on untrusted input.
std::uint64_t file_fingerprint(std::string_view qsp_bytes, const DecodeLimits& limits = {});

// The connectivity `topology` (file_topology()) describes: its components' canonical quads one after
// another, then the unreferenced vertices, numbered as decode() numbers a file that does not keep the
// order; every position is zero. Throws Error(kFormat) for a code partition_from_code() refuses, and
// Error(kLimit) past 2^32 - 1 vertices. Safe on untrusted input.
QuadMesh file_connectivity(const FileTopology& topology);

}  // namespace qsp
