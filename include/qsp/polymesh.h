// qsp/polymesh.h: a polygon mesh with everything a mesh file carries, kept exactly: faces of any
// degree, numbers as the file wrote them, texture coordinates and normals in their own index spaces,
// colours, groups, materials, smoothing groups, OpenSubdiv tags, comments, PLY properties, and the
// order the file had. docs/mesh_model.md says what is per vertex, per corner and per face, and how a
// codec stores each part. Uses only qsp/mesh.h (for QuadMesh and kInvalid).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/mesh.h"
#include "qsp/submesh.h"

namespace qsp {

// How exactly a list of numbers is held. The classes are nested: what float32 holds, float64 holds.
// A number read from text is the decimal value the text denotes ("1.50" and "1.5" are one value);
// float32 holds it when the shortest text of the nearest float32 denotes the same value; float64
// holds every text of up to 17 significant digits (the most a float64 print needs, printf's %.17g):
// the float64 is its value, written back as its shortest text, which reads back to the same float64
// and decides the class ("0.10000000000000001" is 0.1, which float32 holds).
// A binary number is its own value: float32 data is kFloat32, float64 data kFloat64, bit for bit.
enum class Precision : std::uint8_t {
  kFloat32 = 0,  // every value is the shortest text of its float32
  kFloat64 = 1,  // every value is a float64; some need more than float32
  kDecimal = 2,  // some values are decimals of more than 17 significant digits, kept as digits
};

// A value no float64 holds, as the decimal (-1)^negative * digits * 10^exponent.
struct DecimalNumber {
  std::uint32_t index = 0;  // which value of its Numbers
  bool negative = false;
  std::int32_t exponent = 0;
  std::string digits;  // significant digits, no leading or trailing zero (never empty: zero is a float)
};

// A list of numbers kept exactly (see Precision). Mirrors are kept for geometry: `f32` always.
struct Numbers {
  Precision precision = Precision::kFloat32;
  std::vector<float> f32;  // every value rounded to the nearest float32 (the value itself for kFloat32; +-inf
                           // or 0 beyond float32's range)
  std::vector<double> f64;  // precision >= kFloat64: every value rounded to the nearest float64; else empty
  std::vector<DecimalNumber> decimals;  // kDecimal: the values float64 does not hold, by increasing index

  std::size_t size() const { return f32.size(); }
  bool empty() const { return f32.empty(); }
  // The value as a double: exact for kFloat64 and below (kFloat32 gives the float's own value).
  double approx(std::size_t i) const { return f64.empty() ? f32[i] : f64[i]; }
};

// Numbers holding exactly these float32 values.
Numbers numbers_from_float32(std::vector<float> values);
// Numbers holding exactly these float64 values (precision kFloat64).
Numbers numbers_from_float64(const std::vector<double>& values);

// An OpenSubdiv tag: `t name nint/nfloat/nstring ints... floats... strings...`.
struct Tag {
  std::string name;                  // crease, corner, hole, interpolateboundary, ...
  std::vector<std::int64_t> ints;    // as written; tag_indices() says which index vertices or faces
  Numbers floats;                    // sharpness values and the like, exact
  std::vector<std::string> strings;  // creasemethod's "chaikin", ...
};

// What a tag's integer arguments index, by its name (OpenSubdiv regression/common/far_utils.h).
enum class TagIndices : std::uint8_t {
  kNone,      // settings (interpolateboundary, facevaryinginterpolateboundary, creasemethod, ...)
  kVertices,  // corner: vertex indices
  kEdges,     // crease: pairs of vertex indices, one pair per edge
  kFaces,     // hole: face indices
  kUnknown,   // anything else (the hierarchical vertexedit, edgeedit, faceedit): qsp cannot renumber it
};
TagIndices tag_indices(std::string_view name);

// `tags` with their indices renumbered: vertex i becomes vertex[i] (crease pairs, corner vertices), face f
// becomes face[f] (hole faces); settings are unchanged. Throws Error(kUsage) naming the tag for an index
// out of range, a crease with an odd number of indices, or a tag whose indices qsp cannot renumber
// (TagIndices::kUnknown). Safe on untrusted input; O(indices).
void renumber_tags(std::vector<SubdivisionTag>& tags, std::span<const std::uint32_t> vertex,
                   std::span<const std::uint32_t> face);

// ScalarType (qsp/submesh.h) by PLY 1.0's name.
std::string_view scalar_type_name(ScalarType t);  // PLY 1.0's name: "char", "uchar", ..., "double"

// A PLY vertex or face property qsp has no other place for ("quality", "flags", a `texcoord` list).
struct Property {
  std::string name;
  ScalarType type = ScalarType::kFloat32;  // of the values
  bool list = false;
  ScalarType count_type = ScalarType::kUint8;  // a list's length type
  std::vector<std::uint32_t> offsets;  // list: per element and one more, where its values start; else empty
  Numbers values;                      // scalar: one per element; list: the lists end to end
};

// Where a PLY file put each vertex and face property, to write the header back as it was.
enum class PlyFormat : std::uint8_t { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
enum class PlyRole : std::uint8_t {
  kPosition,       // x, y, z (component 0-2)
  kNormal,         // nx, ny, nz, per vertex (corner normals equal corner vertices)
  kTexcoord,       // u, v (or s, t), per vertex
  kColor,          // red, green, blue, alpha: vertex or face colour
  kVertexIndices,  // the face's list of vertices
  kProperty,       // Mesh::vertex_properties / face_properties[index]
};
struct PlyField {
  PlyRole role = PlyRole::kProperty;
  std::uint32_t index = 0;  // component (0-3) or property index
  std::string name;
  ScalarType type = ScalarType::kFloat32;
  ScalarType count_type = ScalarType::kUint8;  // kVertexIndices and list properties
};
struct PlyLayout {
  PlyFormat format = PlyFormat::kAscii;
  bool faces_first = false;            // the face element came before the vertex element
  std::vector<PlyField> vertex, face;  // header order; empty: the writer lays the file out itself
  std::vector<std::string> obj_info;   // `obj_info` header lines' text
};

// A polygon mesh as read: nothing inferred, merged, triangulated or reordered. Each attribute array
// is empty when the file has none of it.
struct Mesh {
  // Vertices
  Numbers positions;                         // 3 per vertex: x, y, z
  Numbers vertex_colors;                     // vertex_color_components per vertex
  std::uint8_t vertex_color_components = 0;  // 0, 3 (r g b) or 4 (r g b a)
  Numbers vertex_weights;                    // OBJ `v x y z w`: 1 per vertex

  // Faces: any degree >= 3, corners in the file's order (counter-clockwise seen from outside)
  std::vector<std::uint32_t> face_offsets;     // per face and one more: its first corner (0, ..., corners)
  std::vector<std::uint32_t> corner_vertices;  // per corner: its vertex

  // Corner attributes, each in its own index space (seams are corners of one vertex with two values)
  Numbers texcoords;                            // texcoord_components per texture coordinate (`vt`)
  std::uint8_t texcoord_components = 2;         // 1 to 3
  std::vector<std::uint32_t> corner_texcoords;  // per corner: its texture coordinate or kInvalid
  Numbers normals;                              // 3 per normal (`vn`)
  std::vector<std::uint32_t> corner_normals;    // per corner: its normal or kInvalid

  // Face attributes
  Numbers face_colors;                     // face_color_components per face
  std::uint8_t face_color_components = 0;  // 0, 1 (OFF colour-map index), 3 or 4
  FaceLabels objects;                      // `o`
  FaceLabels groups;                       // `g`
  FaceLabels materials;                    // `usemtl`
  FaceLabels smoothing;                    // `s` ("off", "1", ...)

  // The file's other content
  std::vector<std::string> material_libraries;  // per `mtllib` statement: its arguments
  std::vector<Tag> tags;                        // OpenSubdiv tags, in file order
  std::vector<std::string> comments;            // comment lines' text after '#' (PLY: after "comment ")
  std::vector<std::string> verbatim;            // OBJ lines kept as text (vp, cstype, prose), file order
  std::vector<Property> vertex_properties;      // PLY
  std::vector<Property> face_properties;        // PLY

  // The order the file had; a writer follows it when present. Empty: canonical order.
  std::vector<Statement> statements;  // OBJ
  PlyLayout ply;                      // PLY

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return face_offsets.empty() ? 0 : face_offsets.size() - 1; }
  std::size_t corner_count() const { return corner_vertices.size(); }
  std::uint32_t degree(std::size_t f) const { return face_offsets[f + 1] - face_offsets[f]; }
};

// Checks every invariant the comments above state (sizes, offsets, indices in range, degrees >= 3, no
// face repeating a vertex, labels, layouts). Throws Error(kUsage) naming the array and index. Safe on
// untrusted input; O(size).
void check_mesh(const Mesh& mesh);

// The categories of data besides positions and faces, for dropping and reporting (the CLI's --drop).
enum Category : unsigned {
  kCategoryUv = 1u << 0,         // texcoords, corner texcoords
  kCategoryNormal = 1u << 1,     // normals, corner normals
  kCategoryColor = 1u << 2,      // vertex and face colours
  kCategoryGroup = 1u << 3,      // objects (o) and groups (g)
  kCategoryMaterial = 1u << 4,   // materials (usemtl) and material libraries (mtllib)
  kCategorySmoothing = 1u << 5,  // smoothing groups (s)
  kCategoryTag = 1u << 6,        // OpenSubdiv tags
  kCategoryComment = 1u << 7,    // comments
  kCategoryExtra = 1u << 8,      // verbatim lines, PLY properties and obj_info, vertex weights
  kCategoryAll = (1u << 9) - 1,  // --positions-only
};

// Each category's name, in the order messages list them: the one table of them (parse_categories,
// category_list, the CLI's --drop and its help).
struct CategoryName {
  std::string_view name;
  Category category;
};
inline constexpr CategoryName kCategoryNames[] = {
    {"uv", kCategoryUv},       {"normal", kCategoryNormal},     {"color", kCategoryColor},
    {"group", kCategoryGroup}, {"material", kCategoryMaterial}, {"smoothing", kCategorySmoothing},
    {"tag", kCategoryTag},     {"comment", kCategoryComment},   {"extra", kCategoryExtra},
};

// The name of one category ("uv"); "" for anything else.
std::string_view category_name(unsigned category);

// The names of `categories` joined by `separator` in kCategoryNames order ("uv,normal"); "" for none.
std::string category_list(unsigned categories, std::string_view separator = ",");

// Parses a comma-separated list of category names (kCategoryNames, "colour" for color, "all" for all of
// them). Throws Error(kUsage) naming an unknown (or empty) one and the valid ones.
unsigned parse_categories(std::string_view list);

// How much of each category a mesh has (or a drop removed).
struct Extras {
  std::uint64_t texcoords = 0, normals = 0;             // values (vt, vn), or per-vertex ones (PLY, OFF)
  std::uint64_t vertex_colors = 0, face_colors = 0;     // coloured vertices, faces
  std::uint64_t objects = 0, groups = 0;                // distinct names
  std::uint64_t materials = 0, material_libraries = 0;  // distinct names, mtllib statements
  std::uint64_t smoothing = 0;                          // distinct smoothing values
  std::uint64_t tags = 0, comments = 0, verbatim = 0;   // tags, comment lines, verbatim lines
  std::uint64_t properties = 0, vertex_weights = 0;     // PLY properties, weighted vertices

  bool any() const;
  // "12 texture coordinates, 3 groups", empty if nothing.
  std::string describe() const;
};

// What `mesh` carries in `categories`.
Extras extras(const Mesh& mesh, unsigned categories = kCategoryAll);

// Removes `categories` from `mesh` (their arrays, their statements and PLY fields) and returns what
// was removed. Positions and faces are never dropped. Never throws for a mesh check_mesh accepts.
Extras drop(Mesh& mesh, unsigned categories);
// The same for a polygon mesh (a decoded .qsp's): its arrays, their exact float64 copies and their OBJ
// statements; returns the categories among `categories` it had. Its leading comment block is not part
// of it (decode_polygons leaves that in the file). Never throws.
unsigned drop(PolygonMesh& mesh, unsigned categories);

// The mesh's quads as a QuadMesh with the float32 mirror of the positions; attributes are ignored.
// Throws kNotQuad when a face is not a quad (naming the first ones, counting all), kBadNumber when a
// position is beyond float32's range.
QuadMesh to_quad_mesh(const Mesh& mesh);

// The mesh as the codec takes it: the float32 mirror of the positions (and their float64 values where
// float32 does not hold them all: a kDecimal list's nearest float64s), the faces as they are, and of
// `categories` what the codec keeps: kCategoryUv its texture coordinates (float32; every corner naming
// one or kInvalid, also when the file has values but no corner names one), kCategoryColor its vertex and
// face colours (float32), kCategoryGroup its objects
// and groups, kCategoryMaterial its materials and material libraries, kCategorySmoothing its smoothing
// groups, kCategoryNormal its normals (float32, as texture coordinates), kCategoryTag its OpenSubdiv tags
// (their floats as binary32 values where the list is kFloat32, else as the nearest binary64: a kDecimal list
// is not held exactly), kCategoryExtra its lines kept as text, its vertex weights (the vertex property
// named "", first) and PLY vertex and face properties (each value exactly as a binary64: a kDecimal list's
// nearest; `float64` where a float list is not kFloat32), not its PLY obj_info lines; every other
// attribute ignored. Never throws but for memory.
PolygonMesh to_polygon_mesh(Mesh mesh, unsigned categories);

// The categories to_polygon_mesh carries into a PolygonMesh.
inline constexpr unsigned kPolygonMeshCategories = kCategoryUv | kCategoryNormal | kCategoryColor |
                                                   kCategoryGroup | kCategoryMaterial | kCategorySmoothing |
                                                   kCategoryTag;

// The inverse of to_polygon_mesh, as decompress writes a decoded mesh: a Mesh holding exactly the
// PolygonMesh's positions (its float64 positions64 where it has them, else its float32 ones) and its faces,
// its texture coordinates (when texcoord_components is not 0) and normals (when it has any) with their
// corners, vertex and face colours (float32), face labels, material libraries, kept lines and OpenSubdiv tags
// (their floats as kFloat64 Numbers where the tag says float64, else as float32), vertex weights and PLY
// properties (kFloat64 Numbers where `float64` says so or an integer is beyond float32); nothing else, and no
// statements (the writers use the canonical order). A Mesh whose numbers are float32 and which carries only
// kPolygonMeshCategories comes back from to_polygon_mesh(m, kPolygonMeshCategories) with the same arrays (a
// corner array it left empty beside values comes back as kInvalid per corner). Checks nothing (check_mesh
// does) and never throws but for memory; safe on untrusted input, as it only moves arrays and indexes none.
Mesh from_polygon_mesh(PolygonMesh mesh);

// A Mesh with exactly the QuadMesh's float32 positions and quads.
Mesh from_quad_mesh(QuadMesh mesh);

}  // namespace qsp
