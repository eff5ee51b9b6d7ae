// The topology and order sections' coders (format-spec/qsp_format.md, "Topology section", "Order
// section"), internal to the codec: codec.cpp and the encoder call them, tests reach them through the
// private include path.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "geometry_coder.h"
#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/regions.h"

namespace qsp {

// Entropy-codes the connectivity of `codes` (canonical order) into the topology section's payload.
// Throws Error(kInternal) if a code is not one partition_from_code would accept.
std::string encode_topology(std::span<const TopologyCode> codes);

// Inverse of encode_topology for `component_count` components. `max_edges` bounds the total number of
// schematic edges and `max_length` any edge length (both derive from the declared face count), so
// memory stays proportional to the declared mesh. `base_offset` is the payload's offset in the file,
// for messages. Throws Error(kFormat). Safe on untrusted input (codes still need partition_from_code).
std::vector<TopologyCode> decode_topology(std::string_view payload, std::uint64_t base_offset,
                                          std::uint64_t component_count, std::uint64_t max_edges,
                                          std::uint64_t max_length);

// The order section's payload.
std::string encode_order(const OrderMap& order);
// Throws Error(kFormat) unless the payload holds exactly two permutations of the given sizes (and the
// rotations); `base_offset` as for decode_topology. Safe on untrusted input.
OrderMap decode_order(std::string_view payload, std::uint64_t base_offset, std::uint32_t vertex_count,
                      std::uint32_t face_count);

// The order section of a polygon file (beside the polygons section): per input vertex its output vertex,
// per input face its output face and rotation r (output corner i is input corner (i + r) mod d), the
// degree d per output face. Throws Error(kInternal) where a rotation is not below its degree.
std::string encode_polygon_order(std::span<const std::uint32_t> vertex, std::span<const std::uint32_t> face,
                                 std::span<const std::uint32_t> rotation,
                                 std::span<const std::uint32_t> degree);
struct PolygonOrder {
  std::vector<std::uint32_t> vertex, face, rotation;
};
// Inverse of encode_polygon_order for `vertex_count` output vertices and the output faces' degrees.
// Throws Error(kFormat) unless the payload holds exactly two permutations and rotations below their
// faces' degrees. Safe on untrusted input.
PolygonOrder decode_polygon_order(std::string_view payload, std::uint64_t base_offset,
                                  std::uint32_t vertex_count, std::span<const std::uint32_t> degree);

// The polygons section's payload (format 3.1) for `codes` over the layout quads `layout_quads` (their
// adjacency `layout_adjacency`): the stream, nothing after it (the geometry section codes the interior
// positions, beside an interior positions section: format 3.12). `rebuilt` receives the faces the
// decoder will rebuild (for the encoder's check and the interior stencils). Throws Error(kInternal) if
// the codes are not canonical_regions' (never writes a wrong file).
std::string encode_polygons_section(std::span<const std::uint32_t> layout_quads,
                                    const Adjacency& layout_adjacency, const RegionCodes& codes,
                                    PolygonFaces* rebuilt = nullptr);

// A polygons section's stream decoded: the faces rebuild_polygons gives, and the bytes after the stream
// (`rest`, at file offset `rest_at`).
struct PolygonStream {
  PolygonFaces faces;
  std::string_view rest;
  std::uint64_t rest_at = 0;
};
// Inverse of encode_polygons_section, up to the positions. Throws Error(kFormat) naming what and the
// byte offset (or the region, face and corner), kLimit past `limits`. Safe on untrusted input: the
// declared counts are checked against the bytes and `limits` before anything is allocated by them.
PolygonStream decode_polygon_stream(std::string_view payload, std::uint64_t base_offset,
                                    std::span<const std::uint32_t> layout_quads,
                                    const Adjacency& layout_adjacency, const DecodeLimits& limits);
// The positions per output vertex: a layout ref's from `layout_positions` (per layout vertex), an owned
// interior ref's from `interior_positions` (3.12: decoded by the geometry section, in ref order; the
// stream must end the section) or, without them (3.1 to 3.11), from the geometry payload after the
// stream, coded along a chain. Throws Error(kFormat) as decode_polygon_stream does. Safe on untrusted
// input.
std::vector<float> polygon_positions(const PolygonStream& stream, std::uint32_t layout_vertices,
                                     std::span<const float> layout_positions,
                                     const std::vector<float>* interior_positions);

// The refs that own an output vertex (the smallest ref of each), in increasing order: those of the
// first output vertices are layout refs, the rest interior refs.
struct InteriorOwners {
  std::vector<std::uint32_t> layout_owner;   // per output vertex u < L: its layout ref
  std::vector<std::uint32_t> interior_refs;  // per owned interior vertex j (output vertex L + j): its ref
};
InteriorOwners interior_owners(const PolygonFaces& faces, std::uint32_t layout_vertices);

// The stencils of the owned interior vertices of `faces` (format 3.12, "Interior positions section"),
// coded after the `layout_vertices` layout vertices: entry j for coding position layout_vertices + j.
// `coding`: the layout vertex at each coding position in patch order, empty in layout order. Time
// O(corners + region corners log degree), so no file makes it quadratic. Safe on decoded faces.
std::vector<Stencil> interior_stencils(const PolygonFaces& faces, std::uint32_t layout_vertices,
                                       std::span<const std::uint32_t> coding);

// What a section of values per corner calls itself in messages, and its fixed component count (0: 1 to
// 3 as the flags say): the texture coordinates section's values, or the normals section's, which codes
// normals as the texture coordinates section codes its values.
struct CornerValueWords {
  const char* section;
  const char* one;
  const char* many;
  unsigned components;
  std::uint64_t DecodeLimits::*limit;  // the decoder's limit on their count
  bool normals = false;  // normals: flag bits 5 (predicted from the faces) and 6 (octahedral) are theirs
};
inline constexpr CornerValueWords kTexcoordWords{"texture coordinates section", "texture coordinate",
                                                 "texture coordinates", 0, &DecodeLimits::max_texcoords};
inline constexpr CornerValueWords kNormalWords{"normals section",          "normal", "normals", 3,
                                               &DecodeLimits::max_normals, true};
// The minor version a texture coordinates section's payload needs: 3.18 with flag bit 5, 3.16 with flag
// bit 7, else 3.2.
inline std::uint8_t texcoords_section_minor(std::string_view payload) {
  const std::uint8_t flags = payload.empty() ? 0 : static_cast<std::uint8_t>(payload[0]);
  return (flags & 0x20)   ? kFormatMinorTexcoordMirror
         : (flags & 0x80) ? kFormatMinorSeamHints
                          : kFormatMinorTexcoords;
}
// The minor version a normals section's payload needs: 3.10 with flag bit 5 or 6, else 3.5.
inline std::uint8_t normals_section_minor(std::string_view payload) {
  return !payload.empty() && (static_cast<std::uint8_t>(payload[0]) & 0x60) ? kFormatMinorNormalsGeometry
                                                                            : kFormatMinorNormals;
}

// The texture coordinates section (format 3.2) of the output mesh whose faces are `face_offsets` (one
// more than faces) and whose corners' vertices are `corner_vertices` (below `vertex_count`, at
// `positions` as the decoder decodes them: 3 per vertex), in the order
// the decoder outputs them before any order section applies. `values` holds `components` (1-3) floats
// per texture coordinate in the input's numbering, `corner_texcoords` per output corner its input index
// or kInvalid. `keep_order` stores the input numbering too. `quantize_bits` 1-24 rounds the values to
// the grid of step 2^-bits (a component with a value of 2^(40 - bits) or more stays exact); 0 keeps
// them exactly. Normals (`words.normals`) are tried predicted from the faces too (the smallest section
// kept), and `quantize_bits` 2-24 makes them octahedral (kept exact if one has zero length). Throws
// Error(kBadNumber) for a value that is not finite, Error(kUsage) for more than 24 bits (1 for
// normals), Error(kInternal) for inconsistent sizes. `sample` > 0: from 2 * `sample` values the predictions
// are compared on about `sample` values spread over the mesh and only the smallest coded whole (0, or
// fewer values: each coded whole, the smallest kept). `mirror` (texture coordinates only): per vertex its
// image under the file's symmetry section's mirror (kInvalid where none; empty: no symmetry section), so
// values may be predicted from their mirror images' (flag bit 5, 3.18) where that is smaller.
std::string encode_texcoords_section(std::span<const std::uint32_t> face_offsets,
                                     std::span<const std::uint32_t> corner_vertices,
                                     std::uint32_t vertex_count, std::span<const float> positions,
                                     std::uint8_t components, std::span<const float> values,
                                     std::span<const std::uint32_t> corner_texcoords, bool keep_order,
                                     std::uint32_t quantize_bits,
                                     const CornerValueWords& words = kTexcoordWords, std::uint32_t sample = 0,
                                     std::span<const std::uint32_t> mirror = {});

struct DecodedTexcoords {
  std::uint8_t components = 0;
  std::vector<float> values;           // components per texture coordinate (input numbering if kept)
  std::vector<std::uint32_t> corners;  // per output corner: its texture coordinate or kInvalid
};
// Inverse of encode_texcoords_section; `order_section` says whether the file has one (the section's
// order bit must agree) and `minor` is the file's minor version (normals' bits 5 and 6 need 3.10).
// `mirror`: per output vertex its mirror image (the symmetry section's, in a file without a polygons
// section), or empty; flag bit 5 without it is refused.
// Throws Error(kFormat) naming what and the byte offset, kLimit past
// `limits.max_texcoords`. Safe on untrusted input: the declared counts are checked against the corners
// and the limits before anything is allocated by them; time and memory linear in them.
DecodedTexcoords decode_texcoords_section(std::string_view payload, std::uint64_t base_offset,
                                          std::span<const std::uint32_t> face_offsets,
                                          std::span<const std::uint32_t> corner_vertices,
                                          std::uint32_t vertex_count, std::span<const float> positions,
                                          bool order_section, const DecodeLimits& limits,
                                          const CornerValueWords& words = kTexcoordWords,
                                          std::uint8_t minor = kFormatMinor,
                                          std::span<const std::uint32_t> mirror = {});

// The colours section (format 3.8) of the output mesh whose faces are `face_offsets` (one more than
// faces) and whose corners' vertices are `corner_vertices` (below `vertex_count`), in the order the
// decoder outputs them before any order section: `vertex_components` (0, 3 or 4) values per output vertex
// in `vertex_colors`, `face_components` (0, 1, 3 or 4) per output face in `face_colors`. `quantize_bits`
// 1-24 rounds them to the grid of step 2^-bits (a component with a value of 2^(40 - bits) or more stays
// exact); 0 keeps them exactly. Throws Error(kBadNumber) for a value that is not finite, Error(kUsage)
// for more than 24 bits, component counts the format has not or arrays of other sizes.
std::string encode_colors_section(std::span<const std::uint32_t> face_offsets,
                                  std::span<const std::uint32_t> corner_vertices, std::uint32_t vertex_count,
                                  std::uint8_t vertex_components, std::span<const float> vertex_colors,
                                  std::uint8_t face_components, std::span<const float> face_colors,
                                  std::uint32_t quantize_bits);
struct DecodedColors {
  std::uint8_t vertex_components = 0, face_components = 0;
  std::vector<float> vertex, face;  // per output vertex, per output face
};
// Inverse of encode_colors_section. Throws Error(kFormat) naming what and the byte offset. Safe on
// untrusted input: the component count the mesh implies is checked against the bytes before anything is
// allocated; time and memory linear in the corners, vertices and faces.
DecodedColors decode_colors_section(std::string_view payload, std::uint64_t base_offset,
                                    std::span<const std::uint32_t> face_offsets,
                                    std::span<const std::uint32_t> corner_vertices,
                                    std::uint32_t vertex_count);

// The names of `l` as the face labels section numbers them: number[i] is name i's number, by the first
// output face g (input face input_face[g]) that takes each, then the names no face takes in their order.
// Throws Error(kUsage) for a face label beyond the names.
std::vector<std::uint32_t> label_numbering(const FaceLabels& l, std::span<const std::uint32_t> input_face);

// Whether mesh.statements differ from the order a decoder's OBJ writer gives the mesh without them
// (io_write.cpp's canonical order): only then is the statement order section worth its bytes.
bool statements_needed(const PolygonMesh& mesh);
// The statement order section (optional): mesh.statements with each label statement's name in the face
// labels section's numbering (`input_face` as for encode_labels_section). Throws Error(kUsage) for a
// comment run or a label beyond its names.
std::string encode_statements_section(const PolygonMesh& mesh, std::span<const std::uint32_t> input_face);
// Inverse of encode_statements_section, checked against the decoded `mesh` (after any order section): the
// runs add up to its arrays, label statements name its names, and each face's labels are the ones the
// statements before it set, so an OBJ writer can follow them. Throws Error(kFormat) naming what and the
// byte offset. Safe on untrusted input: a statement is allocated only after its bytes are read.
std::vector<Statement> decode_statements_section(std::string_view payload, std::uint64_t offset,
                                                 const PolygonMesh& mesh);

// The properties section (format 3.14): PLY vertex and face properties and the OBJ vertex weight (the
// vertex property named ""), each per output vertex (`vertices` of them) and face (`faces`), in the
// decoder's output order before any order section. Throws Error(kUsage) for a property whose arrays
// disagree with its element count, a value its type cannot hold, a float binary32 does not hold that is
// not marked float64, a name a PLY header cannot hold, or more than one vertex weight.
std::string encode_properties_section(const std::vector<ValueProperty>& vertex,
                                      const std::vector<ValueProperty>& face, std::size_t vertices,
                                      std::size_t faces);
struct DecodedProperties {
  std::vector<ValueProperty> vertex, face;
};
// Inverse of encode_properties_section. Throws Error(kFormat) naming the property and byte offset. Safe
// on untrusted input: every count is checked against the bytes left before anything is allocated.
DecodedProperties decode_properties_section(std::string_view payload, std::uint64_t offset,
                                            std::uint64_t vertices, std::uint64_t faces);

// The kept lines section (format 3.7, optional): the lines in order. Throws Error(kUsage) for a line
// kept_line_problem() refuses.
std::string encode_kept_lines_section(const std::vector<std::string>& lines);
// Inverse of encode_kept_lines_section. Throws Error(kFormat) naming the line and byte offset. Safe on
// untrusted input: no line is allocated before its length is checked against the bytes left.
std::vector<std::string> decode_kept_lines_section(std::string_view payload, std::uint64_t offset);
// The PLY obj_info lines section (format 3.15, optional): the lines' text after `obj_info `, in order.
// Throws Error(kUsage) for a line holding a line break.
std::string encode_ply_info_section(const std::vector<std::string>& lines);
// Inverse of encode_ply_info_section. Throws Error(kFormat) naming the line and byte offset. Safe on
// untrusted input: no line is allocated before its length is checked against the bytes left.
std::vector<std::string> decode_ply_info_section(std::string_view payload, std::uint64_t offset);
// The coded comments section's limits: its text (the lines joined by LF) is at most 2^20 bytes and holds
// at most 2^16 lines, so that a decoder's memory is bounded whatever the stream.
inline constexpr std::uint64_t kCodedCommentsMaxText = std::uint64_t{1} << 20;
inline constexpr std::uint64_t kCodedCommentsMaxLines = std::uint64_t{1} << 16;
// Whether `lines` keep to those limits (with_comments writes the plain comments section otherwise).
bool codable_comments(const std::vector<std::string>& lines);
// The coded comments section (format 3.16, optional): the comment lines joined by LF, range-coded
// through a text model. Lines are assumed free of CR and LF and within the limits above (with_comments
// checks both; tests craft invalid sections with it).
std::string encode_coded_comments_section(const std::vector<std::string>& lines);
// Inverse of encode_coded_comments_section. Throws Error(kFormat) naming the byte offset (a text length
// past 2^20 or past what the stream can hold, more than 2^16 lines, a CR, a stream that does not end as
// the encoder ends it). Safe on untrusted input: the text is allocated only after its length is checked
// against both bounds.
std::vector<std::string> decode_coded_comments_section(std::string_view payload, std::uint64_t offset);
// The exact positions section (format 3.6) of the output vertices whose binary32 positions are
// `positions` and exact values `exact` (3 per vertex each, the decoder's output order before any order
// section). Throws Error(kUsage) for an exact value that is not finite or does not round to its position.
std::string encode_exact_section(std::span<const float> positions, std::span<const double> exact);
// The exact positions section's block over any values with `axes` components (modes, widths, residuals:
// qsp_format.md, "Exact positions section", with `axes` for 3). Throws Error(kUsage) as above.
std::string encode_exact_values(std::span<const float> values, std::span<const double> exact,
                                std::size_t axes);
// Inverse of encode_exact_values over the decoded `values`; `section` and `element` name them in messages.
// Throws Error(kFormat) naming the element, axis and byte offset. Safe on untrusted input.
std::vector<double> decode_exact_values(std::string_view payload, std::uint64_t base_offset,
                                        std::span<const float> values, std::size_t axes,
                                        std::string_view section, std::string_view element);
// Whether `exact` says more than `values`: some exact value is neither its binary32 nor the value of that
// binary32's shortest text (what a writer of the binary32 prints: "0.1" needs no exact value).
bool exact_needed(std::span<const float> values, std::span<const double> exact);
// The arrays of the exact values section (format 3.13), kind k at bit k: texture coordinates, normals,
// vertex colours, face colours, each as the decoded mesh returns it (after any order section); `exact`
// empty where the kind has none.
struct ExactArray {
  std::span<const float> values;
  std::span<const double> exact;
  std::size_t axes = 0;
  const char* name = "";     // "texture coordinates", in messages
  const char* element = "";  // "texture coordinate", in messages
};
std::string encode_exact_values_section(std::span<const ExactArray> arrays);
// Its inverse over the decoded arrays (their `exact` unused): per kind its exact values, empty where the
// section has none. Throws Error(kFormat) for a reserved kind bit, a kind whose array is empty, a block
// that is not its array's, bytes after the last. Safe on untrusted input.
std::vector<std::vector<double>> decode_exact_values_section(std::string_view payload,
                                                             std::uint64_t base_offset,
                                                             std::span<const ExactArray> arrays);
// Inverse of encode_exact_section over the decoded `positions`. Throws Error(kFormat) naming what and the
// byte offset. Safe on untrusted input: the payload's size is checked against the vertex count and the
// widths before anything is allocated; time and memory linear in the vertices.
std::vector<double> decode_exact_section(std::string_view payload, std::uint64_t base_offset,
                                         std::span<const float> positions);
// The face labels section (format 3.3; with front-coded names, where smaller, 3.9) of `mesh`, whose output
// face g (the decoder's order before any order section) is input face input_face[g]. Throws Error(kUsage) for
// a label array of another size, a label out of range or a name or library holding a line break.
std::string encode_labels_section(const PolygonMesh& mesh, std::span<const std::uint32_t> input_face);

struct DecodedLabels {
  FaceLabels objects, groups, materials, smoothing;  // per output face, for the kinds the file has
  std::vector<std::string> material_libraries;
};
// Inverse of encode_labels_section for `face_count` output faces of a file of format 3.`minor`. Throws
// Error(kFormat) naming what and the byte offset. Safe on untrusted input: counts are checked against the
// bytes left before anything is allocated by them, front-coded names' total length against 64 bytes a
// payload byte; time and memory linear in the faces and the payload.
DecodedLabels decode_labels_section(std::string_view payload, std::uint64_t base_offset,
                                    std::uint32_t face_count, std::uint8_t minor = kFormatMinor);
// The format minor version a face labels section needs: 3.3, or 3.9 with front-coded names.
std::uint8_t labels_section_minor(std::string_view payload);

// The subdivision tags section (format 3.4) of `tags`: the indices of crease, corner and hole through
// `vertex` and `face` (input index -> output index) unless `keep_order` (the file then has an order
// section and outputs the input's numbering). Throws Error(kUsage) for a name or string that is not one
// word, an index out of range, an odd crease, a float binary32 does not hold without float64, a float
// that is not finite, or a tag qsp cannot renumber without keep_order.
std::string encode_tags_section(std::span<const SubdivisionTag> tags, std::span<const std::uint32_t> vertex,
                                std::span<const std::uint32_t> face, bool keep_order);

// Inverse of encode_tags_section for an output of `vertex_count` vertices and `face_count` faces;
// `order_section` says whether the file has one. Throws Error(kFormat) naming what and the byte offset.
// Safe on untrusted input: every count is checked against the bytes left before it allocates.
std::vector<SubdivisionTag> decode_tags_section(std::string_view payload, std::uint64_t base_offset,
                                                std::uint64_t vertex_count, std::uint64_t face_count,
                                                bool order_section);

}  // namespace qsp
