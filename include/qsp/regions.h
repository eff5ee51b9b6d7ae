// qsp/regions.h: everything of a polygon mesh beyond its quad submesh — the non-quad regions and the
// vertex glue — described canonically against the quad submesh's canonical layout, and rebuilt from it
// (docs/polygon_meshes.md, "Storing it"). No bytes here: the codec serializes these structures.
//
// Reference numbering ("refs"): the quad submesh's layout vertices first, [0, layout_vertices), as the
// codec numbers them (components in canonical order, each in grid_layout order, then the unreferenced
// vertices); then the regions' interior vertices, layout_vertices + i, in region order and, within a
// region, in order of first appearance. Glue groups merge refs into one vertex each; the final vertex
// numbering keeps refs in increasing order of each group's smallest ref.
//
// Boundary loops of the quad submesh ("holes": a schematic's hole faces, an annulus's two rows) are
// named from the layout alone: loops in order of their smallest layout vertex, each walked in the
// direction of its exterior half-edges (the non-quad faces inside it run the same way) from that
// vertex, position 0. (loop, position) names a layout vertex on a hole canonically.
//
// A region is coded by a depth-first traversal of its faces. Each face is entered through a gate, a
// known half-edge whose reverse the face has, and lists its corners from the gate's head, in the
// face's own order: so no rotation is stored. Its remaining corners are coded against two candidates
// the traversal state offers (the open half-edges of the decoded faces and of the quads' holes):
//  - kFollow: the vertex x of the open half-edge x -> p on top at the previous corner p;
//  - kClose:  the vertex y of the open half-edge c0 -> y on top at the face's first corner c0;
//  - kNew:    a new interior vertex (the next ref);
//  - kBoundary (a hole vertex), kInterior (an interior vertex of the region): any other.
// Vertices count as equal when glued (copies of one input vertex): a face may name any copy, and the
// coder names a candidate whenever it is a copy of the corner's vertex, so a face whose corner rule 4
// put on another copy than its quad neighbour's still follows the hole.
// Then each edge of the face that closed no open half-edge says whether an unvisited face of the region
// lies across it (pushed: entered later through it, last pushed first).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/submesh.h"

namespace qsp {

// How a region's traversal starts. A region with a corner on a hole has a face glued to a quad there
// (rule 4 attaches a corner to a quad fan through the faces of its own region), so it has an edge start.
enum class RegionStart : std::uint8_t {
  kEdge = 0,  // through the hole edge from (loop, position): its first face lies across that edge
  kFree = 1,  // at a new interior vertex: the region touches no quad (a triangle mesh, a fin cut off)
};

enum class CornerSymbol : std::uint8_t { kFollow = 0, kClose = 1, kNew = 2, kBoundary = 3, kInterior = 4 };

// One region's canonical code. Faces come in traversal order; the first face lists its corners from
// the start (the hole edge's first vertex, or the free start's new vertex), every other face from its
// gate's head.
struct RegionCode {
  RegionStart start = RegionStart::kFree;
  std::uint32_t loop = 0, position = 0;  // kEdge; 0 for kFree
  std::vector<std::uint32_t> degrees;    // per face: its degree, 3 or 5 and more
  // Per coded corner (an edge-started or gated face codes degree - 2 corners, a free start's first face
  // degree - 1): its symbol.
  std::vector<CornerSymbol> corners;
  // Values, in corner order: per kBoundary two, relative to the last hole vertex this region listed
  // before it (r): (0, steps forward from r along r's loop) on r's loop, else (1 + loop, position);
  // per kInterior one, back (0: the region's newest interior vertex).
  std::vector<std::uint32_t> values;
  // Per edge that closed no open half-edge (in each face's corner order from its second corner; a free
  // start's first face from its first): 1 if a face of the region not yet reached lies across it.
  std::vector<std::uint8_t> open;
};

bool operator==(const RegionCode& x, const RegionCode& y);

// Everything the quad submesh's canonical form does not say. Regions come in canonical order: edge
// starts by (loop, position), then by code; free starts after them (see canonical_regions). Glue groups: each
// the refs of the copies of one input vertex (at least two), increasing; groups in increasing order of their
// first ref.
struct RegionCodes {
  std::uint32_t layout_vertices = 0;    // refs below this are layout vertices
  std::uint32_t interior_vertices = 0;  // kNew symbols in all regions
  std::vector<RegionCode> regions;
  std::vector<std::uint32_t> glue_offsets{0};  // group g is glue[glue_offsets[g] .. glue_offsets[g+1])
  std::vector<std::uint32_t> glue;
};

bool operator==(const RegionCodes& x, const RegionCodes& y);

// The canonical description of a polygon mesh past its quad submesh, and how the input maps onto what
// rebuild_polygons gives back.
struct CanonicalRegions {
  // The quad submesh's canonical form as passed in, except where roots (or components) that tie on
  // topology and positions were chosen between by the region codes and glue they give: the codec must
  // code this one, not the one passed in.
  CanonicalMesh quads;
  RegionCodes codes;
  // Per interior vertex (ref layout_vertices + i): its input vertex, whose position the codec stores.
  std::vector<std::uint32_t> interior_original;
  // What rebuild_polygons returns, in the input's terms: per input vertex its output vertex; per input
  // face its output face (quads in layout order, then region faces in code order) and the rotation r
  // such that output corner i is input corner (i + r) % degree.
  std::vector<std::uint32_t> vertex, face, rotation;
};

// Ties past which the choice is deterministic for a given input but may depend on its numbering
// (docs/polygon_meshes.md, "Ties"): starts compared per free region or cut edge, and the tie search
// among identical quad components and tied roots, whose work (in vertices, corners and glue refs
// looked at) is bounded by kRegionTieCap * (corners + vertices) + kRegionTieFloor; past that, every
// component takes canonicalize's order.
inline constexpr std::uint32_t kRegionTieCap = 64;
inline constexpr std::uint64_t kRegionTieFloor = std::uint64_t{1} << 20;  // work allowed on any mesh

// The canonical region codes and glue of the polygon mesh (face_offsets, corners, vertex_count,
// positions: as quad_submesh takes them; positions may be empty, as zeros) whose quad submesh is
// `submesh` (quad_submesh of the same arrays) with canonical form `quads` (canonicalize of
// submesh.mesh and submesh.adjacency under any partition). Equal for isomorphic polygon meshes with
// the same positions (renumbered vertices and faces, rotated corner lists), up to the ties named
// above. Throws Error(kInternal) if an invariant fails (never a wrong result); the arrays must be the
// ones submesh was cut from (kInternal where sizes disagree). Safe on any mesh quad_submesh accepted:
// O(corners + vertices) and kRegionTieCap times that at most where positions tie exactly, never
// quadratic (a vertex with 25,000 tied one-quad components around it included).
CanonicalRegions canonical_regions(std::span<const std::uint32_t> face_offsets,
                                   std::span<const std::uint32_t> corners, std::uint32_t vertex_count,
                                   std::span<const float> positions, const QuadSubmesh& submesh,
                                   CanonicalMesh quads);

// A polygon mesh as plain arrays: face f has corners[face_offsets[f] .. face_offsets[f+1]).
struct PolygonFaces {
  std::uint32_t vertex_count = 0;
  std::vector<std::uint32_t> face_offsets{0}, corners;
  std::vector<std::uint32_t> ref_vertex;  // per ref: its output vertex (glue merged)
};

// The inverse: the polygon mesh that `codes` describe over the quad layout `layout_quads` (4 layout
// vertex indices per quad, as the codec rebuilds them; `layout_adjacency` = build_adjacency of them
// over codes.layout_vertices vertices). Output vertices: refs with each glue group merged into its
// smallest, in increasing order; faces: the quads, then each region's faces in code order, corners as
// coded. Throws Error(kFormat) naming the region, face and corner (or glue group) where the codes are
// not consistent: a symbol with no candidate, a reference out of range, a face repeating a vertex
// (after gluing too), a degree of 4 or below 3 or above the refs, a gate closed twice, streams too short or
// too long, starts out of order, a glue group of one, unordered or overlapping, or naming a vertex no face
// uses. Safe on untrusted codes: time and memory O(layout vertices + quads + symbols + glue refs); the one
// declared count allocated by, interior_vertices, is checked against the kNew symbols first, and refs
// (layout + interior) at or beyond kPolygonSizeLimit (2^31) are refused. Throws kInternal only if
// layout_quads and layout_adjacency disagree in size (the caller's arrays, not the codes).
PolygonFaces rebuild_polygons(std::span<const std::uint32_t> layout_quads, const Adjacency& layout_adjacency,
                              const RegionCodes& codes);

}  // namespace qsp
