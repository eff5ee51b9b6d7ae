// qsp/permute.h: a mesh renumbered by a vertex and face permutation (with a first corner per face),
// the one copy every stage that reorders a mesh uses: decoding a file that keeps the order, match's
// locality renumbering, reorder_like (match.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "qsp/mesh.h"

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

// The inverse of a permutation: out[p[i]] = i. Throws Error(kUsage) unless `p` is a permutation of
// 0..p.size()-1.
std::vector<std::uint32_t> inverse_permutation(std::span<const std::uint32_t> p);

}  // namespace qsp
