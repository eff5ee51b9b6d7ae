// qsp/permute.h: a mesh renumbered by a vertex and face permutation (with a first corner per face),
// the one copy every stage that reorders a mesh uses: decoding a file that keeps the order, match's
// locality renumbering, reorder_like and reorder_polygons_like (match.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "qsp/mesh.h"
#include "qsp/submesh.h"

namespace qsp {

// A renumbering, read "from": the result's vertex i is `mesh`'s vertex vertex_from[i]; the result's
// face f is `mesh`'s face face_from[f], with its corner c being corner (c + rotation[f]) % 4 of that
// face (rotation empty: corners keep their order). Vertices are renumbered in the faces and their
// positions moved with them; unreferenced vertices move like any other.
struct Renumbering {
  std::span<const std::uint32_t> vertex_from;
  std::span<const std::uint32_t> face_from;
  std::span<const std::uint8_t> rotation;  // empty, or one per face (only the low two bits count)
  // Every face reversed as well: corner c of the result's face f is corner (rotation[f] - c) % 4 of
  // `mesh`'s face face_from[f] (an orientation-reversing renumbering).
  bool reverse = false;
};

// `mesh` renumbered by `r`. Throws Error(kUsage), naming the first offending index, unless vertex_from
// and face_from are permutations of the mesh's vertices and faces and rotation is empty or one per face;
// a face index of `mesh` out of range is reported as the mesh is (kBadIndex). O(V + F); safe on untrusted
// maps.
QuadMesh permute(const QuadMesh& mesh, const Renumbering& r);

// The same for a polygon mesh and everything it carries: the result's face f is `mesh`'s face
// face_from[f] with its corner c being that face's corner (c + first[f]) % d, or (first[f] - c) % d when
// `reverse`, d its degree (first empty: 0).
struct PolygonRenumbering {
  std::span<const std::uint32_t> vertex_from;
  std::span<const std::uint32_t> face_from;
  std::span<const std::uint32_t> first;  // empty, or one per face, below its degree
  bool reverse = false;
  bool renumber_tags = true;  // tags' vertex and face indices follow (else they are kept as they are)
};

// `mesh` renumbered by `r`: vertex attributes (positions, exact positions, colours, properties) move with
// their vertices, face attributes (colours, labels, properties) with their faces, each corner's texture
// coordinate and normal with its corner; value arrays, label names, libraries and kept lines stay as they
// are; tags as `r.renumber_tags` says (renumber_tags, polymesh.h). Throws Error(kUsage) as the quad permute()
// does, for a first corner beyond its face, or a tag that cannot be renumbered. O(V + corners); safe on
// untrusted maps.
PolygonMesh permute(const PolygonMesh& mesh, const PolygonRenumbering& r);

// Vertex or face properties renumbered: element e of each is element from[e] of `props` (a list keeps its
// values in order). Throws Error(kUsage) for a property whose values or list offsets disagree with
// from.size() elements; `from` must be a permutation (the caller's: permute() checks its own). O(values).
std::vector<ValueProperty> permute_properties(const std::vector<ValueProperty>& props,
                                              std::span<const std::uint32_t> from);

// The inverse of a permutation: out[p[i]] = i. Throws Error(kUsage) unless `p` is a permutation of
// 0..p.size()-1.
std::vector<std::uint32_t> inverse_permutation(std::span<const std::uint32_t> p);

}  // namespace qsp
