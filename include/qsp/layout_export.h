// qsp/layout_export.h: a partition seen on its mesh, for people and other tools: which patch each face
// is in, the schematic edges as mesh paths, and the layout exported as a coarse polygon mesh (OBJ) or
// as the mesh tagged by patch (OBJ groups, PLY face property). Text out, never files.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/mesh.h"
#include "qsp/partition.h"
#include "qsp/submesh.h"

namespace qsp {

// A canonical partition on the mesh it was built from. Patches are numbered in canonical order:
// components as canonicalize() orders them, within one the schematic's patch faces in face order (an
// annulus or torus component is one patch). Schematic edges likewise, each as its path of mesh
// vertices from the origin of dart 2e to the origin of dart 2e+1.
struct PatchView {
  std::uint32_t patch_count = 0;
  std::vector<std::uint32_t> face_patch;    // per mesh face: its patch (kInvalid: a face in no patch)
  std::vector<std::uint32_t> patch_colour;  // per patch: a colour class, never a neighbour's (palette index)
  std::vector<std::uint32_t> edge_first;  // per schematic edge e: its path is edge_path[first[e], first[e+1])
  std::vector<std::uint32_t> edge_path;   // mesh vertices of all paths
  std::vector<std::uint32_t> extraordinary;  // mesh vertices, in schematic order
  std::vector<std::uint32_t> t_junctions;    // mesh vertices: schematic vertices of deficiency 0 on a
                                             // patch side but not its corner (where a particle stopped)
  std::uint32_t edge_count() const { return static_cast<std::uint32_t>(edge_first.size()) - 1; }
};

// The view of `canonical` (canonicalize(mesh, adj, partition) of a partition of `adj`). Colours come
// from a greedy colouring of the patches sharing a schematic edge, in canonical order over
// kPatchPalette's classes, so neighbours differ unless a patch has that many neighbours. Deterministic;
// O(mesh faces + schematic).
PatchView view_partition(const Adjacency& adj, const CanonicalMesh& canonical);

// The view of a quad submesh's partition (view_partition of sub.adjacency) carried to the polygon mesh
// of `face_count` faces it was cut from (quad_submesh, qsp/submesh.h): face_patch per polygon face,
// kInvalid for a face that is not a quad; paths and marks on the original vertices (a vertex cut apart
// is one vertex again). Never fails on a matching `sub` and view.
PatchView polygon_view(const QuadSubmesh& sub, const PatchView& quad_view, std::size_t face_count);

// The colour of the faces in no patch (a polygon mesh's triangles and n-gons): a neutral grey.
inline constexpr std::array<std::uint8_t, 3> kNonQuadColour = {178, 178, 178};

// The fixed colours patch classes map to (sRGB), distinct hues that dark lines and dots show on.
inline constexpr std::uint32_t kPatchPaletteSize = 9;
std::array<std::uint8_t, 3> patch_palette(std::uint32_t colour_class) noexcept;

// The partition a .qsp stores, rebuilt on the mesh it decodes to: `codes` are file_topology()'s codes,
// `canonical_to_mesh` maps canonical (decoder layout) vertex numbers to `adj`'s vertices (empty: the
// identity, a file without an order section decoded by decode()). The cuts are the codes' schematic
// edges, found in `adj`, and partition_from_cuts rebuilds the partition along them. Throws
// Error(kFormat) if a schematic edge is not a path of `adj`'s edges (codes of another mesh), and what
// partition_from_cuts throws. Safe on decoded (validated) codes.
Partition stored_partition(const Adjacency& adj, std::span<const TopologyCode> codes,
                           std::span<const std::uint32_t> canonical_to_mesh = {});

// The schematic partition as a polygon mesh (OBJ text): a `v` per schematic vertex (canonical order,
// at its mesh position), an `f` per patch listing the schematic vertices around it counter-clockwise
// from its face_dart corner (corners and T-junction vertices on its sides), each after a comment
// giving its grid size and the mesh lengths of its sides' schematic edges in the same order. Annulus
// and torus components (no schematic vertices) are a comment with their sizes. `header` (one line,
// no newline) is written as the first comment. Never fails.
std::string layout_obj(const QuadMesh& mesh, const CanonicalMesh& canonical, const std::string& header);

// The input mesh with its faces grouped by patch: vertices in input order, exact (shortest text that
// reads back to the same float); OBJ: a `g patch_N` group per patch holding its faces (input order
// within it), a `g non_quads` group with the faces in no patch, then the schematic edges as `l`
// polylines; PLY (ascii): each face with an int property `patch` (-1: in no patch) and its patch's
// colour (uchar red, green, blue; kNonQuadColour for no patch). `view` is view_partition() of the mesh,
// or polygon_view() for a polygon mesh. Never fails.
std::string patches_obj(const PolygonMesh& mesh, const PatchView& view, const std::string& header);
std::string patches_ply(const PolygonMesh& mesh, const PatchView& view, const std::string& header);

}  // namespace qsp
