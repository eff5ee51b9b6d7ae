// qsp/match.h: seed-free isomorphism between two quad meshes through their canonical partitions (§6).
// Isomorphism work happens on the schematic partitions; only the final maps touch every vertex.
// Polygon meshes (faces of any degree, non-manifold and mis-oriented pieces) are matched through their
// quad submesh's canonical form and their canonical region codes and glue (match_polygons, below).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/mesh.h"
#include "qsp/regions.h"
#include "qsp/submesh.h"

namespace qsp {

// What positions are compared when choosing among several isomorphisms (symmetric meshes) and when
// pairing interchangeable components (equal canonical codes).
enum class Centering : std::uint8_t {
  // Translation-invariant (default): components are paired by their centroids relative to each
  // mesh's centroid, and a component's own isomorphism is chosen on positions relative to its own
  // centroid. Moving a whole mesh, or one component, does not change the answer.
  kComponent,
  // Positions relative to each mesh's centroid, everywhere.
  kMesh,
  // Raw positions.
  kNone,
};

// Whether orientation-reversing isomorphisms (every face of B reversed: a mirrored export, flipped
// normals) count.
enum class Mirror : std::uint8_t {
  kNo,      // orientation-preserving only
  kHint,    // only those, but when none exists and B with every face reversed would match, say so
            // (MatchResult::mirror_would_match); costs a second preparation of B in that case
  kAccept,  // an orientation-reversing isomorphism when no orientation-preserving one exists
};

struct MatchOptions {
  Centering centering = Centering::kComponent;
  // Per component, at most this many isomorphisms are scored on all their vertices (the rest are
  // ruled out on a few probe vertices first; see match()). When the cap stops the search before the
  // nearest is certain, the result says so (exhaustive = false, ambiguous = true).
  std::uint32_t max_full_evaluations = 64;
  // Two isomorphisms tie when their costs differ by at most this fraction of the best cost (plus
  // 1e-12 * vertices * bounding-box diagonal², so exact zeros tie too).
  double tie_tolerance = 1e-6;
  // For meshes exported in one vertex order (morphs of a base, re-exports): keep it. Each component's
  // isomorphism is the one moving the fewest vertices away from their own index (A's vertex i to B's
  // vertex i), the distance deciding only among those moving equally few; interchangeable components
  // and unreferenced vertices are paired by index when their indices correspond one to one (else by
  // position). So where the identity of indices is an isomorphism it is the answer, however far a
  // morph moved a symmetric part. Off: the nearest isomorphism, indices play no part.
  bool prefer_order = false;
  Mirror mirror = Mirror::kNo;
};

// The first level at which two meshes differ, coarse to fine. kNone when they are isomorphic.
enum class MatchLevel : std::uint8_t {
  kNone,
  kComponentCount,  // number of connected components
  kComponentSizes,  // multiset of (kind, vertices, faces) per component
  kExtraordinary,   // ... and extraordinary vertices per component
  kSchematic,       // ... and schematic vertices / edges / patches (torus: canonical a x b)
  kCode,            // same sizes, different canonical connectivity (lengths, corners, links, twist)
  kUnreferenced,    // number of vertices in no face
  // Polygon meshes (match_polygons) only:
  kFaceDegrees,  // faces by degree, or the degrees of a non-quad region's faces in canonical order
  kRegions,      // non-quad regions: how many, or how their faces connect to each other and the quads
  kGlue,         // which vertex copies (cut apart at non-manifold or mis-oriented places) are one vertex
};
const char* match_level_name(MatchLevel level) noexcept;

// Per matched component pair.
struct ComponentMatch {
  std::uint32_t a_faces = 0;       // size, to name it in messages
  std::uint64_t isomorphisms = 0;  // orientation-preserving isomorphisms of this pair (= symmetries)
  std::uint32_t scored = 0;        // of them, scored on all vertices
  bool ambiguous = false;          // another isomorphism is as near as the chosen one
  bool exhaustive = true;          // false: the cap stopped the search (then also ambiguous)
  double cost = 0;                 // sum of squared distances of the chosen isomorphism
};

struct MatchResult {
  bool isomorphic = false;
  MatchLevel level = MatchLevel::kNone;  // first level that differs
  std::string reason;                    // one line saying what differs ("" when isomorphic)

  // Mirror::kAccept found an orientation-reversing isomorphism: then corner c of A's face is corner
  // (r - c) % 4 of B's face, r the face's rotation below.
  bool mirrored = false;
  // Mirror::kHint: not isomorphic, but A is isomorphic to B with every face reversed.
  bool mirror_would_match = false;

  // A -> B, filled when isomorphic: B's vertex for each A vertex, B's face for each A face, and the
  // rotation r such that corner c of A's face is corner (c + r) % 4 of B's face (mirrored: (r - c) % 4).
  // Unreferenced vertices are paired by nearest position (minimum total squared distance).
  std::vector<std::uint32_t> vertex;
  std::vector<std::uint32_t> face;
  std::vector<std::uint8_t> rotation;

  // Number of isomorphisms A -> B: product of the components' symmetry counts, times k! for every k
  // interchangeable components and for the k unreferenced vertices. A character with many identical
  // helper parts easily has more than 2^64: `isomorphisms` is exact while the count fits in 64 bits
  // (isomorphisms_exact), else UINT64_MAX; `isomorphisms_log2` is its base-2 logarithm either way
  // (to double precision), so counts of any size compare. isomorphism_count_text() prints it.
  std::uint64_t isomorphisms = 0;
  bool isomorphisms_exact = true;
  double isomorphisms_log2 = 0;
  bool ambiguous = false;  // some choice (a component's isomorphism, a pairing) had an equally near rival
  bool exhaustive = true;  // false when a cap stopped a search early, or a large pairing was greedy
  double cost = 0;         // sum over all vertices of squared distances (as compared, see Centering)
  std::vector<ComponentMatch> components;  // in canonical component order
};

// Finds an orientation-preserving isomorphism (or, as options.mirror says, an orientation-reversing one)
// from `a` to `b` (faces to faces, corners to corners, in
// any numbering, components in any order) without seeds, or says at which level they differ.
//
// How: both meshes are partitioned (motorcycle graph) and canonicalized; equal canonical codes in
// the same order ⇔ isomorphic. The isomorphisms of a component are the starts of its canonical
// traversal (canonical_starts): one per symmetry. Among them match() picks the one minimizing
//     cost = sum over the component's vertices v of |(pos_A(v) - t_A) - (pos_B(map v) - t_B)|²
// (t = the centroid chosen by `options.centering`), which keeps parts where they are. Candidates are
// ranked by the cost over probe vertices (the schematic vertices, or row 0 and column 0 of a torus or
// annulus), a lower bound of their full cost; full costs are computed in that order until the next
// lower bound exceeds the best full cost, so the choice is exact, and usually costs one full pass.
// Components with equal codes are interchangeable: they are paired by minimum total squared centroid
// distance (exactly, Hungarian method, up to 256 of them; greedy nearest-free up to 8192; sorted
// order beyond, exact only when the centroids are equal), then each pair as above.
//
// Time: O(V + F) for adjacency, partition and maps, plus work on the schematics; a and b are prepared
// on two threads. Throws what build_adjacency / partition_motorcycle throw for invalid meshes (Error).
MatchResult match(const QuadMesh& a, const QuadMesh& b, const MatchOptions& options = {});

// One mesh made ready for matching: adjacency, motorcycle partition and canonical form. Prepare a
// reference once to match it against many meshes.
struct MatchInput {
  // The mesh, renumbered for memory locality when its face order is scrambled (then vertex_old /
  // face_old map its vertices / faces to the caller's; empty when not renumbered). Corners keep
  // their order. match() reports everything in the caller's numbering.
  QuadMesh mesh;
  std::vector<std::uint32_t> vertex_old, face_old;
  Adjacency adjacency;
  CanonicalMesh canonical;
  std::array<double, 3> centroid{};  // of all vertices
};

// Prepares `mesh` (pass it by std::move to avoid a copy). A mesh whose consecutive faces rarely share
// a vertex (a file renumbered at random) is first renumbered along a Morton curve: the later stages
// walk it 2-3x faster. Throws what build_adjacency throws, with face/vertex indices of `mesh` as given.
MatchInput prepare_match(QuadMesh mesh);
// With an adjacency already built (build_adjacency(mesh)); never renumbers.
MatchInput prepare_match(const QuadMesh& mesh, const Adjacency& adjacency);

// match() on prepared meshes: what match() returns for the meshes given to prepare_match, its maps in
// their numbering (not that of a renumbered a.mesh or b.mesh). Meshes that differ are a result (isomorphic
// false; `level` and `reason` say where), not an error. Throws only Error(kInternal) for a broken invariant.
// Checks nothing of `a` and `b`: safe on any meshes prepare_match accepted, which is where an untrusted mesh
// is checked; a MatchInput put together by hand is trusted as it is.
MatchResult match(const MatchInput& a, const MatchInput& b, const MatchOptions& options = {});

// The number of isomorphisms of `r` as a person reads it: exact in decimal while it fits in 64 bits
// ("24"), else "about 2^245.3 (6.8e73)". "0" when not isomorphic.
std::string isomorphism_count_text(const MatchResult& r);

// `in` renumbered like `ref`, given m = match(ref, in): vertex i of the result is in's vertex
// m.vertex[i], face f is in's face m.face[f] starting at the corner ref's face f starts at (reversed
// when m.mirrored). So the result's faces are ref's exactly (the same quads array, ref's orientation)
// and its positions are in's: anything stored per vertex, face or face corner of ref applies to it
// unchanged. Throws Error(kUsage)
// when `m` is not isomorphic or its maps are not permutations of in's vertices and faces
// (permute(), permute.h). O(V + F).
QuadMesh reorder_like(const QuadMesh& in, const MatchResult& m);

// True when `m` (from match(a, b)) is a valid isomorphism: vertex map a bijection, and every face f of
// `a` has corner c equal to corner (c + rotation) of face face[f] of `b` under the vertex map
// ((rotation - c) when m.mirrored). O(V + F).
// If not, `why` (when given) says where it fails.
bool verify_match(const QuadMesh& a, const QuadMesh& b, const MatchResult& m, std::string* why = nullptr);

// ---- Polygon meshes: faces of any degree, non-manifold and mis-oriented pieces (docs/matching.md) ----

// One polygon mesh made ready for matching and fingerprinting: its quad submesh (submesh.h), the
// motorcycle partition's canonical form of it and the canonical region codes and glue (regions.h),
// all computed on the topology alone. The positions canonical_regions breaks ties by are replaced by
// vertex colours (colour refinement: a vertex's colour, then its corners' face degrees and the colours
// of their neighbouring corners, until the classes stop splitting), which no renumbering changes; so
// the codes are equal for isomorphic meshes whatever their positions, up to the ties regions.h names.
struct PolygonMatchInput {
  PolygonMesh mesh;
  CanonicalRegions regions;  // its `quads` moved into quads.canonical
  MatchInput quads;          // the quad submesh, its adjacency and canonical form (positions: the colours)
  // Faces by degree, increasing: (degree, count).
  std::vector<std::pair<std::uint32_t, std::uint64_t>> degrees;
  PolygonCounts counts;  // the quad submesh's (submesh.h)
  // Every vertex in a face has a colour of its own: an isomorphism onto another mesh maps each vertex
  // to the one of the same colour, so there is at most one (up to faces with equal corner lists).
  bool rigid = false;
  // A region with no quad vertex (a triangle mesh, a fin) whose corners tie on colours more than
  // kRegionTieCap times: canonical_regions compares only the first kRegionTieCap starts, so its code may
  // depend on the numbering (match refuses rather than answer "not isomorphic" on it).
  bool capped = false;
  std::array<double, 3> centroid{};    // of all vertices
  std::vector<std::uint64_t> colours;  // per vertex: its colour
  // When not rigid: the canonical regions made with every vertex that shares its colour told apart by
  // its own index. match_polygons makes B's with each such vertex told apart by the index of the nearest
  // A vertex of its colour (classes of 64 at most; larger ones: the A vertex at exactly its position):
  // where the two agree (B a renumbered copy, or A moved a little) they give the nearest isomorphism,
  // taken where nearer than the topological one.
  std::shared_ptr<const CanonicalRegions> individual;
};

// Prepares `mesh`. Throws what quad_submesh throws (kBadIndex, kDegenerateFace naming the face, kLimit),
// kUsage when face_offsets is not 0, increasing, ..., corners.size() or positions are not 3 per vertex
// referenced. Safe on untrusted input. Time O((corners + vertices) log) for the colours (at most 64
// rounds), then what quad_submesh, canonicalize and canonical_regions cost (twice when not rigid).
PolygonMatchInput prepare_polygon_match(PolygonMesh mesh);

// What match_polygons finds. As MatchResult, with rotations modulo each face's degree.
struct PolygonMatchResult {
  bool isomorphic = false;
  MatchLevel level = MatchLevel::kNone;  // first level that differs
  std::string reason;                    // "level: what differs" ("" when isomorphic)
  bool mirrored = false;                 // Mirror::kAccept took an orientation-reversing isomorphism
  bool mirror_would_match = false;       // Mirror::kHint: B with every face reversed would match
  // A -> B when isomorphic: B's vertex per A vertex, B's face per A face, and r such that corner c of A's
  // face is corner (c + r) % d of B's face (mirrored: (r - c) % d), d its degree. Unreferenced vertices
  // are paired by nearest position.
  std::vector<std::uint32_t> vertex, face, rotation;
  // The only isomorphism (A rigid, see PolygonMatchInput), or, with prefer_order, the identity of
  // indices; else one of possibly several, not searched for the nearest.
  bool unique = false;
  bool identity = false;        // prefer_order found the identity of indices to be an isomorphism
  bool same_positions = false;  // every vertex of A maps to a vertex of B at exactly its position
  // Not unique, but B's canonical form with its vertices told apart by their nearest A vertices agreed
  // with A's (PolygonMatchInput::individual): symmetric vertices go to their nearest candidates.
  bool snapped = false;
  double cost = 0;         // sum over vertices of squared distances (Centering: kComponent as kMesh)
  bool ambiguous = false;  // unreferenced vertices paired with an equally near alternative
};

// Isomorphism of polygon meshes, orientation-preserving (a face maps to a face of the same degree,
// corners in the same cyclic order), through the canonical forms: the face degrees first, then the quad
// submeshes' levels as match() names them, then the regions (kFaceDegrees where a region's degrees
// differ, else kRegions), then the glue (kGlue). options.mirror as for match(); options.prefer_order:
// when A is not rigid, the identity of indices is taken where it is an isomorphism, and otherwise
// Error(kUnsupported) says the order-keeping search is for all-quad meshes only; centering decides the
// reported cost, the pairing of unreferenced vertices and the nearest A vertex each symmetric B vertex is
// told apart by (PolygonMatchInput::individual; `snapped`): the nearest isomorphism of a symmetric polygon
// mesh is not searched exhaustively, as it is for quad meshes. Throws
// Error(kUnsupported) when either mesh is `capped` and the codes differ (the answer could be wrong),
// kInternal if the maps fail verify_polygon_match (a bug: never a wrong map).
PolygonMatchResult match_polygons(const PolygonMatchInput& a, const PolygonMatchInput& b,
                                  const MatchOptions& options = {});

// True when `m` (from match_polygons(a, b)) is a valid isomorphism: vertex and face maps bijections, and
// every face f of `a` has the degree of face face[f] of `b` and corner c equal to its corner
// (c + rotation) % d ((rotation - c) % d when mirrored) under the vertex map. O(V + corners). If not,
// `why` (when given) says where it fails.
bool verify_polygon_match(const PolygonMesh& a, const PolygonMesh& b, const PolygonMatchResult& m,
                          std::string* why = nullptr);

// `in` renumbered like `ref`, given m = match_polygons(ref, in): vertex i of the result is in's vertex
// m.vertex[i] (its position), face f is in's face m.face[f] listed from the corner ref's face f starts at
// (in reverse when m.mirrored). So the result's faces are ref's exactly and its positions are in's, and
// every attribute of in goes with its vertex, face or corner: exact positions and vertex colours, face
// colours and labels, each corner's texture coordinate and normal (their value arrays and the label names
// as in's), tags renumbered (renumber_tags); libraries and kept lines as in's.
// Throws Error(kUsage) when `m` is not isomorphic or its maps are not bijections onto in's vertices and
// faces of the right degrees, or a tag cannot be renumbered (naming it). O(V + corners).
PolygonMesh reorder_polygons_like(const PolygonMesh& in, const PolygonMatchResult& m);

}  // namespace qsp
