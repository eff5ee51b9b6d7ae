// qsp/codec.h: the .qsp file format (format-spec/qsp_format.md): mesh <-> bytes. Never touches files.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/geometry.h"
#include "qsp/mesh.h"
#include "qsp/partition.h"
#include "qsp/submesh.h"

namespace qsp {

// The format version this library writes: the lowest whose sections the file holds. 3.18 for texture
// coordinates predicted from their mirror images', where that is smaller, 3.17 for positions
// predicted from their mirror images (the symmetry section), where that is smaller, 3.16 for texture
// coordinates coded with hints from the faces across or comments coded through the range coder (the coded
// comments section), where that is smaller, 3.15 for PLY obj_info lines
// (PolygonMesh::ply_info), 3.14 for PLY properties or OBJ vertex weights (PolygonMesh::vertex_properties,
// face_properties), 3.13 for texture coordinates, normals or colours binary32 does not hold, 3.12 for a
// polygon mesh with interior vertices, 3.11 for a kept statement order, 3.10 for normals predicted from the
// faces or octahedral, 3.9 for front-coded label names, 3.7 for a mesh with kept lines
// (PolygonMesh::kept_lines), 3.6 for a lossless mesh with coordinates binary32 does not hold
// (PolygonMesh::positions64), 3.5 for a mesh with normals, 3.4 for a mesh with OpenSubdiv tags, 3.3 for a
// mesh with face labels or material libraries, 3.2 for a mesh with texture coordinates, 3.1 for a polygon
// mesh (its polygons section) or a file with a comments section, 3.0, the first release format, for a
// manifold, consistently oriented all-quad mesh otherwise (the same bytes as before 3.1, unless mirror
// prediction makes it smaller). It reads every 3.x
// file (the required sections a newer minor may add excepted, which it refuses with "upgrade qsp"); 1.x
// and 2.x were development versions and are not read (format-spec/qsp_format.md, "Version").
inline constexpr std::uint8_t kFormatMajor = 3;
inline constexpr std::uint8_t kFormatMinor = 18;
// Texture coordinates predicted from their mirror images' (flag bit 5; the symmetry section's mirror).
inline constexpr std::uint8_t kFormatMinorTexcoordMirror = 18;
// Positions predicted from their mirror images (the symmetry section; geometry tool bit 0x20).
inline constexpr std::uint8_t kFormatMinorMirror = 17;
// The leading comment block coded through a text model (the coded comments section, optional).
inline constexpr std::uint8_t kFormatMinorCodedComments = 16;
// Texture coordinates with hints from the faces across and residuals by activity (flag bit 7).
inline constexpr std::uint8_t kFormatMinorSeamHints = 16;
// A PLY file's obj_info header lines (the PLY obj_info lines section, optional).
inline constexpr std::uint8_t kFormatMinorPlyInfo = 15;
// PLY vertex and face properties and the OBJ vertex weight (the properties section).
inline constexpr std::uint8_t kFormatMinorProperties = 14;
// Texture coordinates, normals and colours binary32 does not hold (the exact values section).
inline constexpr std::uint8_t kFormatMinorExactValues = 13;
// A polygon mesh's interior positions coded by the geometry section (the interior positions section).
inline constexpr std::uint8_t kFormatMinorInterior = 12;
inline constexpr std::uint8_t kFormatMinorStatements = 11;  // the statement order section (optional)
// Normals predicted from the decoded faces, and octahedral normals (normals section flag bits 5 and 6).
inline constexpr std::uint8_t kFormatMinorNormalsGeometry = 10;
inline constexpr std::uint8_t kFormatMinorNames = 9;  // front-coded label names (face labels section)
inline constexpr std::uint8_t kFormatMinorColors = 8;
inline constexpr std::uint8_t kFormatMinorKeptLines = 7;
inline constexpr std::uint8_t kFormatMinorExact = 6;
inline constexpr std::uint8_t kFormatMinorNormals = 5;
inline constexpr std::uint8_t kFormatMinorTags = 4;
inline constexpr std::uint8_t kFormatMinorLabels = 3;
inline constexpr std::uint8_t kFormatMinorTexcoords = 2;
inline constexpr std::uint8_t kFormatMinorPolygons = 1;
inline constexpr std::uint8_t kFormatMinorQuads = 0;

// Compression levels, as gzip's and zstd's: 1 is the fastest, 9 the smallest. Every level is canonical
// (isomorphic meshes with the same positions give the same bytes) and every file decodes with the same
// decoder; a level only decides how much the encoder searches.
inline constexpr int kMinLevel = 1, kMaxLevel = 9, kDefaultLevel = 2;
// Above this many vertices a mesh is coded in one partition (the motorcycle graph) and one coding order
// with sampled headers at every level: the search would multiply a long compress for a fraction of a
// percent.
inline constexpr std::uint64_t kSearchVertexLimit = 32768;

// What a level searches. Every field has one meaning; level_effort() is the one place that sets them.
struct Effort {
  bool all_partitions = false;      // also greedy and merge; keep the smallest file (first on a tie)
  bool both_orders = false;         // patch and layout order; keep the smaller geometry section
  std::uint32_t header_sample = 0;  // GeometryOptions::header_sample (0: every header coded in full)
  bool try_chaining = false;        // GeometryOptions::try_chaining
  bool try_costly_tools = false;    // cell shapes + logistic mixing, kept where smaller (full header trials)
  bool repeats_must_pay = false;    // GeometryOptions::repeats_must_pay
  bool try_mirror = true;           // positions predicted from their mirror images where smaller
  bool operator==(const Effort&) const = default;
};

// The search of `level` for a mesh of `vertex_count` vertices (kSearchVertexLimit applied). Throws
// Error(kUsage) unless kMinLevel <= level <= kMaxLevel.
Effort level_effort(int level, std::uint64_t vertex_count);
// One line saying what `level` searches, for --help and stats. Throws as level_effort does.
std::string level_description(int level);

struct EncodeOptions {
  std::uint32_t quantize_bits = 0;  // 0 = lossless; 1..30 = uniform grid (GeometryOptions)
  // Texture coordinates: 0 = exact; 1..24 = rounded to the grid of step 2^-bits in texture space (12:
  // 1/4096, a texel of a 4096-wide texture), whatever other values the mesh has.
  std::uint32_t quantize_texcoord_bits = 0;
  // Vertex and face colours: 0 = exact; 1..24 = rounded to the grid of step 2^-bits (8: 1/256).
  std::uint32_t quantize_color_bits = 0;
  // Normals: 0 = exact; 2..24 = octahedral, two integers of BITS bits per normal (Draco's -qn; 10 keeps
  // every normal within 0.17 degrees). A mesh with a normal of zero length keeps them exact.
  std::uint32_t quantize_normal_bits = 0;
  bool keep_order = false;    // also store vertex order, face order and first corners
  int level = kDefaultLevel;  // kMinLevel..kMaxLevel: how much the encoder searches (Effort)
  // Threads the encoder may use: 0 = as it sees fit (at most two), 1 = this thread only. The bytes
  // are the same for every count.
  unsigned threads = 0;
  // Which structured partition to store; any decodes with the same decoder (all three are canonical).
  // nullopt: the level decides (Effort::all_partitions, else the motorcycle graph).
  std::optional<PartitionMode> partition;
  // Geometry coding order (geometry_section.md, "Coding orders and stencils"). nullopt: the level decides
  // (Effort::both_orders, else patch order, which is smaller on nearly every mesh measured).
  std::optional<CodingOrder> geometry_order;
};

// What a decoder accepts before allocating. The defaults suit real assets (tens of millions of
// faces); the decoder's memory is then bounded by the declared counts (see the spec, "Limits").
struct DecodeLimits {
  std::uint64_t max_vertices = std::uint64_t{1} << 26;
  std::uint64_t max_faces = std::uint64_t{1} << 26;
  std::uint64_t max_texcoords = std::uint64_t{1} << 26;  // texture coordinates (format 3.2)
  std::uint64_t max_normals = std::uint64_t{1} << 26;    // normals (format 3.5)
};

// The keep-order permutations, as the encoder stores them: for each original vertex its canonical
// index, for each original face its canonical index and the rotation r such that canonical corner c
// is original corner (c + r) % 4.
struct OrderMap {
  std::vector<std::uint32_t> vertex;
  std::vector<std::uint32_t> face;
  std::vector<std::uint8_t> rotation;
};

// Encodes `mesh` (build_adjacency -> partition -> canonicalize -> bytes). The bytes depend only on the
// mesh up to orientation-preserving isomorphism and its positions (plus, with keep_order, the original
// numbering): every partition mode is canonical, and so is choosing the smallest file among them. Throws what
// build_adjacency throws for invalid meshes, Error(kLimit) past the format's limits, Error(kInternal) if a
// stage broke an invariant (never writes a wrong file). If `order` is given it receives the original ->
// canonical map (what decode() numbers vertices and faces by without keep_order), whether or not it is
// stored.
std::string encode(const QuadMesh& mesh, const EncodeOptions& options = {}, OrderMap* order = nullptr);

// `file` (a whole .qsp) with the comments section or the coded comments section holding `lines` (the
// leading comment block of the mesh file it was made from: io.h's leading_comments), whichever is
// smaller (the comments section on a tie, and always for more than 2^16 lines or 2^20 bytes joined),
// replacing any either had; neither for no lines. The file then says the lowest minor version its
// sections need (3.16 with the coded comments section, at least 3.1 with the comments section; never
// more than it said before, other than for the comments); a decoder that predates either section skips
// it. Throws Error(kUsage) for a
// line with a CR or LF (it would be two lines, or a statement, when written back) and what container parsing
// throws for a malformed `file`.
std::string with_comments(std::string_view file, const std::vector<std::string>& lines);

// The comment lines a .qsp's comments or coded comments section holds (empty if it has neither). Checks
// the container as decode() does; Error(kFormat) naming the byte offset for a malformed section (a
// count the bytes cannot hold, a line with a CR or LF, bytes left over, a stream that does not end as
// the encoder ends it, both sections in one file). Safe on untrusted input.
std::vector<std::string> file_comments(std::string_view bytes);

// Why an OBJ line kept as text (PolygonMesh::kept_lines) cannot be stored in the kept lines section
// (format 3.7): written back it would not read as a line kept as text (empty, a control byte, a leading
// '#', a trailing backslash, or a first word that is a statement qsp reads, such as a malformed `t`
// tag). Empty when it can be stored. Never throws but for memory.
std::string kept_line_problem(std::string_view line);

// Decodes a whole .qsp of a quad mesh. Returns the mesh in canonical order (or the original order when
// the file has an order section). A file with a polygons section (3.1) or another required section added
// after 3.0 (texture coordinates, face labels, subdivision tags, normals; the first in tag order is named) is
// refused with Error(kNotQuad): decode_polygons reads it. Throws Error with kFormat (malformed, truncated,
// trailing bytes), kVersion (newer major), kChecksum, kLimit (past `limits`); the message says what and at
// which byte offset. The checksum is verified before anything is decoded. Safe on untrusted input.
QuadMesh decode(std::string_view bytes, const DecodeLimits& limits = {});

// Encodes any polygon mesh. A manifold, consistently oriented all-quad mesh gives exactly encode()'s
// bytes (format 3.0); any other gets the quad submesh (qsp/submesh.h) stored as a 3.0 file stores a quad
// mesh, plus the polygons section (format 3.1) with the non-quad faces and the vertex glue
// (qsp/regions.h) and the interior vertices' positions. Canonical as encode(): renumbering vertices,
// reordering faces and rotating corner lists gives the same bytes (up to regions.h's ties). Throws what
// quad_submesh and build_adjacency throw for what is not a mesh (kBadIndex, kDegenerateFace naming the
// face, as for a quad mesh), Error(kUsage) for a partial element, face offsets that do not cover the
// corners or quantize_bits past 30 (keep_order stores the polygon mesh's own numbering),
// Error(kLimit) past the format's limits, Error(kInternal) if a stage broke an invariant (never writes a
// wrong file). Texture coordinates (mesh.texcoord_components 1-3) go into the texture coordinates section
// (format 3.2) after the faces' canonical order, exactly or rounded as options.quantize_texcoord_bits
// says: Error(kUsage) for arrays that disagree with their component count or a corner naming one past
// the array, Error(kBadNumber) for a value that is not finite. Face labels (objects, groups, materials,
// smoothing groups) and material libraries go into the face labels section (format 3.3): Error(kUsage)
// for a label array of another length than the faces, a label past its names, or a name or library
// holding a line break. OpenSubdiv tags go into the subdivision tags section (format 3.4), the indices
// of crease, corner and hole renumbered with the mesh: Error(kUsage) for an index out of range, a tag
// qsp cannot renumber (vertexedit, ...) without options.keep_order, or a name or string that is not one
// word. Normals (3 per normal, each corner naming one or kInvalid) go into the normals section (format
// 3.5), coded as texture coordinates are, or predicted from the faces naming them (3.10) where that is
// smaller, or octahedral (3.10) as options.quantize_normal_bits says: the same errors for their arrays
// and values, Error(kUsage) for 1 or more than 24 bits. Without
// quantization, positions64 (when not empty) goes into the exact positions section (format 3.6) and the
// geometry codes the binary32 nearest each value: Error(kUsage) for another length than positions or a
// value that is not finite. Kept lines go into the kept lines section (format 3.7, optional):
// Error(kUsage) for one kept_line_problem() refuses.
std::string encode_polygons(const PolygonMesh& mesh, const EncodeOptions& options = {});

// Decodes any .qsp, 3.0 to 3.5: a 3.0 file gives its quads (as decode()), a 3.1 file the polygon mesh:
// the same faces, each with its corner cycle (rotated), on the same vertices up to renumbering; positions
// as stored (exact, or quantized); a file with texture coordinates (3.2) also every corner's, in their
// original order with an order section; a file with face labels (3.3) each face's labels and the
// material libraries; a file with subdivision tags (3.4) the tags; a file with normals (3.5) every
// corner's, as texture coordinates. Same errors as decode(), kLimit also for
// more vertices (interior ones included) or faces than `limits`. Safe on untrusted input: every count is
// checked against the bytes left and `limits` before anything is allocated by it; time and memory linear in
// the file and limits.
PolygonMesh decode_polygons(std::string_view bytes, const DecodeLimits& limits = {});

// Whether a .qsp needs decode_polygons(): it holds a polygon mesh (the polygons section, 3.1), texture
// coordinates (3.2), face labels (3.3), subdivision tags (3.4), normals (3.5) or exact positions (3.6),
// which decode() refuses with kNotQuad, or kept lines (3.7, optional: decode() skips them); from its
// container alone (magic, version, size, checksum, sections' framing), decoding nothing, so a caller can
// choose its reader before decoding once. Throws what decode() throws for a malformed container (kFormat,
// kVersion, kChecksum). Safe on untrusted input.
bool holds_polygons(std::string_view bytes);

struct SectionInfo {
  std::uint8_t tag = 0;
  std::uint64_t offset = 0;  // of the tag byte
  std::uint64_t size = 0;    // tag + length + payload
};

struct ComponentSummary {
  ComponentKind kind = ComponentKind::kUnstructured;
  std::uint32_t vertices = 0, faces = 0;
  std::uint32_t schematic_vertices = 0, schematic_edges = 0, patches = 0;  // 0 for annulus/torus
  std::uint32_t a = 0, b = 0, twist = 0;                                   // annulus/torus
};

// What `qsp stats` prints for a .qsp: the Table-1 row and where the bytes go.
struct FileInfo {
  std::uint8_t version_major = 0, version_minor = 0;
  std::uint8_t level = 0;  // the compression level that wrote the file, 1-9; 0 if it does not say
  std::uint64_t total_bytes = 0;
  std::uint64_t header_bytes = 0;        // magic, version, flags, size, checksum
  std::uint64_t connectivity_bytes = 0;  // counts + topology sections (+ polygon_connectivity_bytes)
  std::uint64_t geometry_bytes = 0;      // the geometry section (+ polygon_positions_bytes)
  // A polygon file's polygons section: its counts and region codes (the non-quad faces, the glue of
  // cut vertices) and, before 3.12, the positions of the vertices no quad has.
  std::uint64_t polygon_connectivity_bytes = 0, polygon_positions_bytes = 0;
  // From 3.12: how many vertices no quad has the geometry section codes (the interior positions
  // section; their bytes are in geometry_bytes, with the layout's).
  std::uint64_t interior_positions = 0;
  std::uint64_t order_bytes = 0;      // keep-order permutations, and the OBJ statement order (3.11)
  std::uint64_t texcoord_bytes = 0;   // the texture coordinates section (3.2; 0 if absent)
  std::uint64_t label_bytes = 0;      // the face labels section (3.3; 0 if absent)
  std::uint64_t tag_bytes = 0;        // the subdivision tags section (3.4; 0 if absent)
  std::uint64_t normal_bytes = 0;     // the normals section (3.5; 0 if absent)
  std::uint64_t exact_bytes = 0;      // the exact positions section (3.6; 0 if absent)
  std::uint64_t color_bytes = 0;      // the colours section (3.8; 0 if absent)
  std::uint64_t property_bytes = 0;   // the properties section (3.14; 0 if absent)
  std::uint64_t comment_bytes = 0;    // the leading comment block: comments (3.1) or coded comments (3.16)
  std::uint64_t kept_line_bytes = 0;  // lines kept as text (3.7) and PLY obj_info lines (3.15)
  std::uint64_t other_bytes = 0;      // optional sections this decoder skipped
  std::uint8_t geometry_tools = 0;    // qsp/geometry.h's geometry_tool bits (geometry_tool_names() says them)
  std::uint8_t quantize_bits = 0;     // 0: lossless positions; 1..30: quantized to that many bits
  CodingOrder geometry_order = CodingOrder::kLayout;  // the order the positions were coded in
  std::uint64_t vertices = 0, edges = 0, faces = 0, unreferenced = 0, extraordinary = 0;
  std::uint64_t schematic_vertices = 0, schematic_edges = 0, patches = 0;
  std::array<std::uint32_t, 4> kind_counts{};  // by ComponentKind
  // A polygon mesh (its polygons section, 3.1): the counts and components above are its quad
  // submesh's; decode_polygons gives the mesh.
  bool polygons = false;
  bool keep_order = false;
  std::vector<ComponentSummary> components;  // canonical order
  std::vector<SectionInfo> sections;
};

// Parses and checks a .qsp like decode() (checksum, limits, topology) without decoding positions,
// and counts what the file holds. Same errors as decode(). Safe on untrusted input.
FileInfo inspect(std::string_view bytes, const DecodeLimits& limits = {});

// The connectivity a whole .qsp stores: its topology codes (components in canonical order) and the
// number of unreferenced vertices after them. Checks as inspect() does, for any version it reads; same
// errors as decode(). Safe on untrusted input.
struct FileTopology {
  std::vector<TopologyCode> codes;
  std::uint64_t unreferenced = 0;
};
FileTopology file_topology(std::string_view bytes, const DecodeLimits& limits = {});

// The keep-order permutations a .qsp stores, as encode() wrote them (empty vectors when the file has
// no order section): with them, decode()'s numbering can be related to the canonical layout's. Checks
// as inspect() does; same errors as decode(). Safe on untrusted input.
OrderMap file_order(std::string_view bytes, const DecodeLimits& limits = {});

}  // namespace qsp
