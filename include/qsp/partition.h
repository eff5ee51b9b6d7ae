// qsp/partition.h: the motorcycle graph (paper §5) and the schematic partition it induces (§4).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/mesh.h"

namespace qsp {

// The edges traced by the particles of §5. One particle starts on every non-boundary edge at an
// extraordinary vertex, moving outward; all move in lockstep, one edge per step. A particle stops when
// it reaches a vertex reached at an earlier step (extraordinary vertices count as reached at step 0),
// reaches a boundary vertex, meets another head-on, or arrives together with two or three others.
// Exactly two arriving perpendicularly at a fresh vertex: let F be the face whose corner at the vertex
// lies between the two incoming tracks; the particle arriving along F's own half-edge continues.
struct MotorcycleGraph {
  std::vector<std::uint32_t> traced;  // one half-edge per traced edge, in the direction it was travelled
  std::uint32_t particles = 0;        // particles started
  std::uint32_t steps = 0;            // lockstep rounds until the last particle stopped
};

// Traces the particles from `extraordinary` (any order, no duplicates) over `adj`. Time and memory are
// proportional to the traced edges (hash tables, no per-vertex arrays): the sublinear path of §5.
// The result depends only on connectivity and orientation, not on vertex or face numbering.
MotorcycleGraph trace_motorcycles(const Adjacency& adj, std::span<const std::uint32_t> extraordinary);

// What a connected component is, once cut. Components with no extraordinary vertex are structured
// (Lemma 2): a disk is one patch; an annulus or torus has no schematic vertex and is stored by its sizes.
enum class ComponentKind : std::uint8_t { kUnstructured = 0, kDisk = 1, kAnnulus = 2, kTorus = 3 };

// "unstructured", "disk", "annulus", "torus" (as `qsp stats --verbose` and `qsp match` print them).
const char* component_kind_name(ComponentKind kind) noexcept;

// A schematic partition (§4) as a winged-edge structure stored by darts. Edge e has darts 2e and
// 2e+1, running opposite ways (twin = d ^ 1); a dart's face lies on its left, so walking `dart_next`
// goes counter-clockwise around a face. The wings of edge e are dart_next/dart_prev of its two darts.
// Faces are patches (four corners, an (a,b)-grid) or holes (no corners, one per mesh boundary loop).
struct Schematic {
  std::uint32_t vertex_count = 0;
  std::vector<std::uint32_t> dart_vertex;  // per dart: the schematic vertex it leaves
  std::vector<std::uint32_t> dart_next;    // per dart: next dart around its face
  std::vector<std::uint32_t> dart_prev;    // per dart: previous dart around its face
  std::vector<std::uint32_t> dart_face;    // per dart: the face on its left
  std::vector<std::uint8_t> dart_corner;   // per dart: 1 if its origin is a corner of its face
  std::vector<std::uint32_t> edge_length;  // per edge: mesh edges along the path (>= 1)
  std::vector<std::uint32_t> face_dart;    // per face: a dart of it; for a patch, one leaving a corner
  std::vector<std::uint8_t> face_hole;     // per face: 1 for a hole, 0 for a patch

  // Link to the mesh it was built from (empty when decoded from bytes).
  std::vector<std::uint32_t> vertex_mesh;    // per schematic vertex: its mesh vertex
  std::vector<std::uint32_t> dart_halfedge;  // per dart: the first mesh half-edge of its path

  std::uint32_t edge_count() const { return static_cast<std::uint32_t>(edge_length.size()); }
  std::uint32_t dart_count() const { return static_cast<std::uint32_t>(dart_vertex.size()); }
  std::uint32_t face_count() const { return static_cast<std::uint32_t>(face_dart.size()); }
  std::uint32_t patch_count() const;
};

// Grid sizes of patch `face`: a along the side leaving face_dart[face], b along the next side.
struct PatchSize {
  std::uint32_t a = 0, b = 0;
};
// Each is the sum of edge_length from corner to corner; a hole, which has no corners, gives its loop's
// length and b = 0. O(the darts of two sides); never throws. Checks nothing: `s` must be a schematic
// validate() accepts (every partition qsp builds or decodes is one) and `face` below s.face_count();
// on anything else it may read out of range or not end.
PatchSize patch_size(const Schematic& s, std::uint32_t face);

// One connected component, cut by its motorcycle graph.
struct ComponentPartition {
  ComponentKind kind = ComponentKind::kUnstructured;
  std::uint32_t component = 0;  // component id in Adjacency::face_component
  std::uint32_t extraordinary = 0;
  Schematic schematic;  // kUnstructured and kDisk
  // kAnnulus: a = edges around, b = rows; kTorus: the lattice {(a,0),(twist,b)}, 0 <= twist < a.
  std::uint32_t a = 0, b = 0, twist = 0;
  // kAnnulus/kTorus: the mesh half-edge at grid origin, running along +x with cell (0,0) on its left.
  std::uint32_t anchor_halfedge = kInvalid;
};

struct Partition {
  std::vector<ComponentPartition> components;  // in Adjacency component order
  std::vector<std::uint32_t> unreferenced;     // vertices in no face, increasing
};

// Motorcycle-graph partition of every component (§4-§5). Throws Error(kInternal) if a patch fails to
// be a grid (it never returns a wrong partition). Needs a valid Adjacency (build_adjacency).
Partition partition_motorcycle(const Adjacency& adj);

// Partition along any set of cut edges (each given by either of its half-edges; boundary edges are
// always cut), e.g. a smaller partition than the motorcycle graph's. Throws Error(kInternal) naming
// the problem if a region is not an (a,b)-grid whose boundary is cut at schematic vertices: a cut set
// must leave every extraordinary vertex with no two consecutive uncut edges, and no region an annulus.
// `check_tiling` false leaves out the checks that the patches' layouts map one-to-one onto the mesh,
// and the region checks that implies (every region a patch with one boundary loop; every patch a
// grid, every schematic checked, still): for a caller that checks the layouts it uses itself (the
// encoder checks its canonical layouts in full, encode_canonical).
Partition partition_from_cuts(const Adjacency& adj, std::span<const std::uint32_t> cuts,
                              bool check_tiling = true);

// Which structured partition to build. All three give partitions that partition_from_cuts has validated
// (every patch an (a,b)-grid, exact tiling), so any of them decodes with the same decoder:
//   kMotorcycle  the motorcycle graph of §5 (partition_motorcycle).
//   kGreedy      §7's path-at-a-time construction from the extraordinary vertices, then the merge pass
//                (qsp/smaller.h).
//   kMerge       the motorcycle graph, then repeated merging of two patches whose union is a grid.
// All three are canonical: every choice is ordered by structure and then by the canonical dart labels
// of a canonical schematic, so isomorphic meshes get isomorphic partitions (equal TopologyCodes). On a
// mesh with symmetries several labellings are canonical; given the positions, greedy and merge take
// the one the codec would (smallest positions), so a renumbered copy gets the same partition, not just
// an isomorphic one, and the same .qsp bytes.
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
// accepted. `check_tiling` false: as partition_from_cuts' for the motorcycle graph (the heuristics'
// partitions are always checked in full: their fallback depends on it).
Partition partition(const Adjacency& adj, PartitionMode mode, std::span<const float> positions = {},
                    bool check_tiling = true);

// Checks every condition of §4's definition of a schematic partition, and — when the schematic is
// linked to `adj` — that its patches tile the component exactly once as (a,b)-grids. Returns an empty
// string when valid, otherwise what is wrong.
std::string validate(const ComponentPartition& part, const Adjacency* adj = nullptr);

// The mesh a component partition stands for, numbered canonically from the schematic alone:
// schematic vertices in order, then each edge's inner vertices (from dart 2e's origin), then each
// patch's inner vertices row by row from its face_dart corner; faces patch by patch, row by row,
// each starting at its lower-left grid corner. This is what the decoder emits (format-spec/
// qsp_format.md, "Grid layout"). Throws Error(kFormat) for a schematic that cannot be laid out.
struct GridLayout {
  std::uint32_t vertex_count = 0;
  std::vector<std::uint32_t> quads;  // 4 per face
};
GridLayout grid_layout(const ComponentPartition& part);

// For a partition linked to a mesh: layout vertex -> mesh vertex, layout face -> mesh face and the
// rotation r such that layout corner c is mesh corner (c + r) % 4.
struct LayoutMap {
  std::vector<std::uint32_t> vertex;
  std::vector<std::uint32_t> face;
  std::vector<std::uint8_t> rotation;
};
LayoutMap layout_to_mesh(const ComponentPartition& part, const Adjacency& adj);

// The tiling half of validate(): `map` (from layout_to_mesh) covers the component's faces and
// vertices exactly once. The scratch vectors may be shared across calls (they are left zeroed), which
// keeps a whole mesh at O(n). Returns an empty string or what is wrong.
std::string check_tiling(const ComponentPartition& part, const Adjacency& adj, const LayoutMap& map,
                         std::vector<std::uint8_t>& face_seen, std::vector<std::uint8_t>& vertex_seen);

}  // namespace qsp
