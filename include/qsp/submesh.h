// qsp/submesh.h: any polygon mesh, cut canonically into a manifold, consistently oriented mesh and its
// quad submesh (the part the motorcycle graph runs on), with what is needed to glue it back.
//
// Input everywhere: plain arrays, so any mesh model can call it. Face f has the corners
// face_offsets[f] .. face_offsets[f+1]-1 (counter-clockwise seen from outside); corners[c] is the
// vertex at corner c, below vertex_count. Corner c is also the half-edge from corners[c] to the next
// corner of its face.
//
// The rules (README "Polygon meshes: the quad submesh", docs/polygon_meshes.md):
//  1. Edges: an edge (two vertices) is glued when exactly two faces have it and they traverse it in
//     opposite directions. Every other edge with two or more faces is cut: each face keeps its own copy
//     (an edge with 3+ faces, or two neighbours of opposite orientation). No face is ever flipped or
//     reordered, so a Möbius band is cut exactly where its faces' corner orders disagree.
//  2. Vertices: the faces at a vertex, joined across glued edges, form fans; each fan gets its own copy.
//     Result: a manifold, consistently oriented polygon mesh (ManifoldCut).
//  3. Quad submesh: faces of degree != 4 are removed; they leave holes in it, where particles stop as at
//     any boundary and deficiency is counted in the quads alone. A vertex copy whose quads form several
//     fans (quads joined across glued edges between quads) gets one copy per quad fan.
//  4. Regions: the non-quad faces joined across glued edges. A region's interior vertices are the
//     copies of step 2 with no quad. A non-quad corner at a copy that has quads is attached to the
//     first quad fan met turning counter-clockwise around the vertex from it, or, where the fan of
//     step 2 ends first, the first turning clockwise.
// Every rule looks only at the faces around an edge or a vertex and their cyclic corner orders, so the
// result depends only on the mesh up to renumbering vertices and faces and rotating corner lists.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "qsp/mesh.h"

namespace qsp {

// A per-face label (OBJ o, g, usemtl, s): an index per face into the distinct values.
struct FaceLabels {
  std::vector<std::uint32_t> face;  // per face: index into `names`, kInvalid before the file's first
                                    // statement of this kind; empty when the file has none
  std::vector<std::string> names;   // the values, in order of first statement (g: names separated by ' ')

  bool empty() const { return face.empty() && names.empty(); }
};

// An OpenSubdiv tag (OBJ `t name nint/nfloat/nstring ints floats strings`) as the codec keeps it.
struct SubdivisionTag {
  std::string name;                  // crease, corner, hole, interpolateboundary, ...
  std::vector<std::int64_t> ints;    // vertex indices (crease: pairs; corner), face indices (hole), or as is
  std::vector<double> floats;        // each a binary32 value unless float64
  bool float64 = false;              // some float needs binary64
  std::vector<std::string> strings;  // creasemethod's "chaikin", ...
};

// A PLY scalar type; integers are kept as exact values.
enum class ScalarType : std::uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

// A per-vertex or per-face property qsp has no other place for, as the codec keeps it: a PLY property
// ("quality", "flags", a `texcoord` list) or the OBJ vertex weight (`v x y z w`: the vertex property
// named "", a scalar float).
struct ValueProperty {
  std::string name;                            // the PLY property's name; "" for the OBJ vertex weight
  ScalarType type = ScalarType::kFloat32;      // of the values
  bool list = false;                           // a list per element (offsets) rather than one value
  ScalarType count_type = ScalarType::kUint8;  // a list's length type (an integer type)
  bool float64 = false;  // a float type some value of which binary32 does not hold (written as binary64)
  std::vector<std::uint32_t> offsets;  // list: per element and one more, where its values start; else empty
  std::vector<double> values;          // exact: scalar: one per element; list: the lists end to end
};

// One OBJ statement, or a run of them, in file order. Runs consume the next entries of their array.
enum class ObjStatement : std::uint8_t {
  kVertex,           // run of `v`
  kTexcoord,         // run of `vt`
  kNormal,           // run of `vn`
  kFace,             // run of `f`
  kObject,           // one `o`; value: index into Mesh::objects.names
  kGroup,            // one `g`; value: index into Mesh::groups.names
  kMaterial,         // one `usemtl`; value: index into Mesh::materials.names
  kSmoothing,        // one `s`; value: index into Mesh::smoothing.names
  kMaterialLibrary,  // run of `mtllib`
  kTag,              // run of `t`
  kComment,          // run of comment lines
  kVerbatim,         // run of lines kept as text
};
struct Statement {
  ObjStatement kind;
  std::uint32_t value;  // a run's length, or a label's index
};

// A polygon mesh as plain arrays: faces of any degree >= 3, face f with corners
// corners[face_offsets[f] .. face_offsets[f+1]) counter-clockwise seen from outside; it may be
// non-manifold and have pieces of either orientation. What the codec (encode_polygons) and matching
// (prepare_polygon_match) take.
struct PolygonMesh {
  std::vector<float> positions;  // 3 per vertex
  // The exact values, where binary32 does not hold them all: empty, or 3 per vertex. A lossless encode
  // keeps them and codes the binary32 nearest each as its position (a reader's own binary32 of the text,
  // in `positions`, differs by an ulp where the float64 lies halfway between two: 1.0000000596046448);
  // a quantized one codes `positions`.
  std::vector<double> positions64;
  std::vector<std::uint32_t> face_offsets{0};  // per face and one more: its first corner
  std::vector<std::uint32_t> corners;          // per corner: its vertex
  // Texture coordinates (OBJ `vt`) in their own index space, so seams are kept; all empty when none.
  std::uint8_t texcoord_components = 0;         // 0 (none), or 1 to 3 per texture coordinate
  std::vector<float> texcoords;                 // texcoord_components per texture coordinate
  std::vector<std::uint32_t> corner_texcoords;  // per corner: its texture coordinate or kInvalid
  // Normals (OBJ `vn`) in their own index space, as texture coordinates; both empty when none.
  std::vector<float> normals;                 // 3 per normal
  std::vector<std::uint32_t> corner_normals;  // per corner: its normal or kInvalid
  // Colours: vertex colours (r g b [a]) and face colours (an OFF colour-map index, or r g b [a]).
  std::uint8_t vertex_color_components = 0;  // 0 (none), 3 or 4
  std::vector<float> vertex_colors;          // vertex_color_components per vertex
  std::uint8_t face_color_components = 0;    // 0 (none), 1, 3 or 4
  std::vector<float> face_colors;            // face_color_components per face
  // The exact values of the four arrays above, where binary32 does not hold some value (a text of more
  // digits, binary64 PLY data): empty, or one double per float of the array beside it, whose binary32
  // value it must round to. A lossless encode keeps them (the exact values section, format 3.13); one
  // that quantizes an array codes its floats.
  std::vector<double> texcoords64, normals64, vertex_colors64, face_colors64;
  // Face labels (OBJ o, g, usemtl, s) and the material libraries (`mtllib` arguments); empty when none.
  FaceLabels objects, groups, materials, smoothing;
  std::vector<std::string> material_libraries;
  std::vector<SubdivisionTag> tags;     // OpenSubdiv tags in file order; indices in this mesh's numbering
  std::vector<std::string> kept_lines;  // OBJ lines kept as text (vp, cstype, prose), file order
  // PLY properties and the OBJ vertex weight, per vertex and per face; empty when none.
  std::vector<ValueProperty> vertex_properties, face_properties;
  std::vector<std::string> ply_info;  // PLY `obj_info` header lines' text, in order
  // The OBJ file's statement order (Mesh::statements, its comment runs left out: the leading comment
  // block goes first), kept with --keep-order: runs consume the arrays above in order, label statements
  // name their kind's names by index. Empty: none kept (writers use the canonical order).
  std::vector<Statement> statements;
  // Positions (binary32) and faces only: no attribute, label, tag, property, kept or obj_info line, or
  // statement order.
  bool bare() const {
    return texcoord_components == 0 && corner_normals.empty() && normals.empty() &&
           vertex_color_components == 0 && face_color_components == 0 && positions64.empty() &&
           !has_labels() && tags.empty() && kept_lines.empty() && vertex_properties.empty() &&
           face_properties.empty() && ply_info.empty() && statements.empty();
  }
  bool has_labels() const {
    return !objects.empty() || !groups.empty() || !materials.empty() || !smoothing.empty() ||
           !material_libraries.empty();
  }
  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return face_offsets.empty() ? 0 : face_offsets.size() - 1; }
  std::uint32_t degree(std::size_t f) const { return face_offsets[f + 1] - face_offsets[f]; }
};

// The same mesh as a PolygonMesh (every face of degree 4). Never throws but for memory.
PolygonMesh polygon_mesh(QuadMesh mesh);

// corners + vertex_count must stay below this: every copy, half-edge and corner index fits in 31 bits,
// and the quad submesh stays inside build_adjacency's limits. Time and memory are O(corners + vertices)
// (counting sorts and single walks, nothing sorted by comparison, no recursion); peak memory about 40
// bytes per corner, the adjacency included. No other limit: a vertex of any valence, an edge with any
// number of faces or a region of any size costs its size.
inline constexpr std::uint64_t kPolygonSizeLimit = std::uint64_t{1} << 31;

// Step 1-2: the manifold, consistently oriented polygon mesh over vertex copies.
struct ManifoldCut {
  std::vector<std::uint32_t> corners;        // per corner: the copy at it (face_offsets unchanged)
  std::vector<std::uint32_t> copy_original;  // per copy: its original vertex
  // Copy v < vertex_count is original vertex v itself: the fan holding v's first corner, or v with no
  // face at all; further copies follow, in the order of their fans' first corners.
  std::uint32_t cut_edges = 0;     // edges cut by rule 1
  std::uint32_t cut_vertices = 0;  // original vertices given more than one copy
};

// Cuts the mesh by rules 1-2. Throws Error: kBadIndex (vertex index >= vertex_count), kDegenerateFace (a
// face repeats a vertex, or has fewer than 3 corners), with build_adjacency's messages naming the face;
// kLimit beyond kPolygonSizeLimit; kInternal if face_offsets is not 0, increasing, ..., corners.size().
// Safe on untrusted input; O(corners + vertices).
ManifoldCut cut_manifold(std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> corners,
                         std::uint32_t vertex_count);

// Faces by degree and what was cut (for `qsp stats`).
struct PolygonCounts {
  std::uint32_t quads = 0, triangles = 0, ngons = 0;  // faces of degree 4, 3, 5 or more
  std::uint32_t cut_edges = 0;                        // edges cut by rule 1
  std::uint32_t cut_vertices = 0;  // original vertices with more than one submesh vertex (rules 2-4)
  std::uint32_t extra_copies = 0;  // submesh vertices beyond one per original vertex used by a face
};

// A connected region of non-quad faces (rule 4): it lies in holes of the quad submesh, or on its own.
struct NonQuadRegion {
  std::vector<std::uint32_t> faces;     // original face indices, increasing
  std::vector<std::uint32_t> interior;  // its submesh vertices that no quad uses (>= mesh.vertex_count())
  std::vector<std::uint32_t> loops;     // boundary loops of the quad submesh it touches, increasing
};

struct QuadSubmesh {
  // The quads in input order, each with its corners in input order, over the submesh vertices
  // [0, mesh.vertex_count()): first one per original vertex that a quad or no face uses (in original
  // order; its quad fan holding its first quad corner), then the further quad-fan copies by first
  // corner. So an all-quad manifold oriented mesh comes out as itself. Positions are copied from the
  // original vertex.
  QuadMesh mesh;
  Adjacency adjacency;  // build_adjacency(mesh)
  // Per submesh vertex: its original vertex. Submesh vertices [mesh.vertex_count(), size()) are the
  // regions' interior vertices (copies no quad uses), in the order of their fans' first corners.
  std::vector<std::uint32_t> vertex_original;
  std::vector<std::uint32_t> corner_vertex;  // per input corner: its submesh vertex (rule 4 for non-quads)
  std::vector<std::uint32_t> quad_face;      // per quad: its original face
  std::vector<NonQuadRegion> regions;        // numbered by their smallest face
  // Boundary loops of the quad submesh (a schematic's hole faces, an annulus's two rows): per loop its
  // smallest exterior half-edge of `adjacency`; per exterior half-edge (h - 4 * face_count) its loop.
  std::vector<std::uint32_t> loop_halfedge;
  std::vector<std::uint32_t> exterior_loop;
  PolygonCounts counts;
};

// Cuts the mesh by rules 1-4 and builds the quad submesh and its adjacency. `positions` holds 3 floats
// per original vertex, or is empty (the submesh's positions are then zero; fill them from
// vertex_original). Gluing back: corners[c] == vertex_original[corner_vertex[c]] for every corner.
// Throws what cut_manifold throws, kInternal if `positions` has another size, or if the quad submesh
// fails build_adjacency (a bug: never a wrong result). Safe on untrusted input; O(corners + vertices).
QuadSubmesh quad_submesh(std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> corners,
                         std::uint32_t vertex_count, std::span<const float> positions = {});

}  // namespace qsp
