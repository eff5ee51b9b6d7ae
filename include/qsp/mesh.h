// qsp/mesh.h: the compact face-vertex quad mesh and its half-edge adjacency.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace qsp {

inline constexpr std::uint32_t kInvalid = 0xFFFFFFFFu;

// A quad mesh exactly as read: float32 positions as parsed, faces in file order. Unreferenced vertices
// are kept (they carry data); nothing is inferred or dropped.
struct QuadMesh {
  std::vector<float> positions;  // 3 per vertex: x, y, z
  std::vector<std::uint32_t>
      quads;  // 4 per face, 0-based vertex indices, counter-clockwise seen from outside

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return quads.size() / 4; }
};

// Half-edge adjacency of a QuadMesh, built in O(n).
// Interior half-edge h = 4*f + i runs from corner i to corner (i+1)%4 of face f, so `next` is implicit.
// Every boundary edge also gets one exterior half-edge (index >= 4F) that lies in the hole and runs
// the other way; `twin` is therefore always valid and rotation around a vertex needs no special case.
struct Adjacency {
  std::uint32_t vertex_count = 0;
  std::uint32_t face_count = 0;
  std::vector<std::uint32_t> twin;    // per half-edge: the half-edge on the other side of its edge
  std::vector<std::uint32_t> origin;  // per half-edge: the vertex it leaves
  std::vector<std::uint32_t>
      exterior_next;  // per exterior half-edge (index h - 4F): next one around its hole
  std::vector<std::uint32_t> vertex_halfedge;  // per vertex: one outgoing half-edge (the exterior one on the
                                               // boundary), kInvalid if unreferenced
  std::vector<std::uint32_t> valence;          // per vertex: number of incident edges (0 if unreferenced)
  std::vector<std::uint8_t> boundary;          // per vertex: 1 if on the mesh boundary
  std::vector<std::uint32_t> face_component;   // per face: connected component id, numbered by first face
  std::vector<std::uint32_t> component_faces;  // per component: its number of faces
  std::uint32_t component_count = 0;

  std::uint32_t halfedge_count() const { return static_cast<std::uint32_t>(twin.size()); }
  bool is_exterior(std::uint32_t h) const { return h >= 4 * face_count; }
  std::uint32_t next(std::uint32_t h) const {
    return h < 4 * face_count ? (h & ~3u) | ((h + 1) & 3u) : exterior_next[h - 4 * face_count];
  }
  // Inside a face the next corner is in the same cache line: no twin lookup needed.
  std::uint32_t dest(std::uint32_t h) const { return h < 4 * face_count ? origin[next(h)] : origin[twin[h]]; }
  std::uint32_t face(std::uint32_t h) const { return h < 4 * face_count ? h >> 2 : kInvalid; }
  // Next outgoing half-edge around origin(h), turning clockwise seen from outside.
  std::uint32_t rotate(std::uint32_t h) const { return next(twin[h]); }
  // Deficiency D(v): 4 - d inside, 3 - d on the boundary (paper §3). Unreferenced vertices: 0.
  int deficiency(std::uint32_t v) const {
    if (valence[v] == 0) return 0;
    return (boundary[v] ? 3 : 4) - static_cast<int>(valence[v]);
  }
  // Extraordinary (paper §2): interior valence != 4, or boundary valence > 3.
  bool extraordinary(std::uint32_t v) const {
    return valence[v] != 0 && (boundary[v] ? valence[v] > 3 : valence[v] != 4);
  }
};

// The largest mesh qsp handles, the same in every stage: the readers (io.h), build_adjacency and the
// .qsp format (Error kLimit beyond, kFormat for a file declaring more). build_adjacency numbers up to 8
// half-edges per face (4 interior, at most 4 exterior) in uint32, and vertex ids stay below kInvalid.
inline constexpr std::uint64_t kMaxFaces = (std::uint64_t{1} << 29) - 1;
inline constexpr std::uint64_t kMaxVertices = (std::uint64_t{1} << 31) - 1;

// At most n threads for each qsp call from now on, process-wide: 1 = every function runs on its
// caller's thread only (no helper thread, no waiting for one); 0 (the default) or more = a second
// thread where it pays (qsp never uses more than two at once for one call). EncodeOptions::threads = 1
// asks the same for one encode. Results never depend on it. Thread-safe.
void set_thread_limit(unsigned n);

// Builds the adjacency and checks that the mesh is an orientable 2-manifold with quad faces.
// Throws Error: kBadIndex (index >= vertex count), kDegenerateFace (repeated vertex in a face),
// kNonManifold (edge with 3+ faces, vertex with several fans), kOrientation (two faces traverse an
// edge the same way); messages name the face or vertex (0-based). kLimit past kMaxFaces or
// kMaxVertices, kUsage for arrays that end inside a vertex or face. Safe on untrusted input.
// `threads`: 1 = this thread only; 0 = a second thread from 4096 faces; 2 or more = two threads on
// any mesh (tests). The result and the errors never depend on it.
Adjacency build_adjacency(const QuadMesh& mesh, unsigned threads = 0);
// The same for `quads` (4 vertex indices per face) over `vertex_count` vertices, without positions.
// One thread unless asked: the decoder runs it beside its geometry, where the other core is busy.
Adjacency build_adjacency(std::span<const std::uint32_t> quads, std::uint32_t vertex_count,
                          unsigned threads = 1);

// Per connected component (of faces): vertex, edge and face counts and Euler characteristic.
struct ComponentInfo {
  std::uint32_t vertices = 0, edges = 0, faces = 0, boundary_edges = 0, extraordinary = 0;
  std::int64_t euler() const { return static_cast<std::int64_t>(vertices) - edges + faces; }
  std::int64_t deficiency_sum = 0;  // sum of D(v) over the component's vertices (Lemma 1: = 4*euler)
};
// Per component of `adj` (indexed by Adjacency::face_component's ids), its counts; unreferenced
// vertices are in none. O(V + F). Never throws but for memory; checks nothing of `adj`, so it is safe on any
// mesh build_adjacency accepted, and an Adjacency put together otherwise may read out of range.
std::vector<ComponentInfo> component_info(const Adjacency& adj);

// Extraordinary vertices in increasing index order.
std::vector<std::uint32_t> extraordinary_vertices(const Adjacency& adj);

}  // namespace qsp
