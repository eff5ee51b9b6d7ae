// Reading a .qsp (format-spec/qsp_format.md): the container (container.h), the counts, the topology
// rebuilt into component partitions and laid out, the geometry decoded along the layout's stencils,
// the order section; and inspect, file_topology and file_order on the same checked parse.
#include "qsp/codec.h"

#include <algorithm>
#include <future>
#include <iterator>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "beside.h"
#include "bytes.h"
#include "codec_sections.h"
#include "container.h"
#include "geometry_coder.h"
#include "mirror.h"
#include "qsp/error.h"
#include "qsp/permute.h"
#include "stencil.h"

namespace qsp {
namespace {

using container::Section;

[[noreturn]] void format_error(const std::string& what, std::uint64_t offset) {
  throw Error(ErrorCode::kFormat, what + " (at byte offset " + std::to_string(offset) + ")");
}

struct Counts {
  std::uint64_t vertices = 0, faces = 0, components = 0, unreferenced = 0;
};

// Everything up to (not including) geometry decoding: what decode() and inspect() share.
struct Parsed {
  container::File file;
  const Section* topology = nullptr;
  const Section* geometry = nullptr;
  const Section* order = nullptr;
  Counts counts;
  std::vector<TopologyCode> codes;
  std::vector<ComponentPartition> parts;
  std::vector<std::uint32_t> comp_vertices, comp_faces;
  std::vector<std::uint32_t> mirror;  // per layout vertex its mirror image (lay_out, with a symmetry section)
  std::optional<Adjacency> adjacency;  // the layout's, checked, where lay_out built it for the mirror
};

// The container, then the counts, checked against the format and the caller's limits before anything
// is allocated.
Parsed parse(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p;
  p.file = container::parse(bytes);
  p.topology = p.file.find(container::kTagTopology);
  p.geometry = p.file.find(container::kTagGeometry);
  p.order = p.file.find(container::kTagOrder);
  const Section& cs = *p.file.find(container::kTagCounts);
  ByteReader c(cs.payload, cs.payload_offset);
  std::uint64_t off = c.offset();
  p.counts.vertices = c.varint("vertex count");
  if (p.counts.vertices > kMaxVertices) format_error("vertex count exceeds the format's 2^31 - 1", off);
  if (p.counts.vertices > limits.max_vertices) {
    throw Error(ErrorCode::kLimit, "vertex count " + std::to_string(p.counts.vertices) +
                                       " exceeds the limit " + std::to_string(limits.max_vertices) +
                                       " (at byte offset " + std::to_string(off) + ")");
  }
  off = c.offset();
  p.counts.faces = c.varint("face count");
  if (p.counts.faces > kMaxFaces) format_error("face count exceeds the format's 2^29 - 1", off);
  if (p.counts.faces > limits.max_faces) {
    throw Error(ErrorCode::kLimit, "face count " + std::to_string(p.counts.faces) + " exceeds the limit " +
                                       std::to_string(limits.max_faces) + " (at byte offset " +
                                       std::to_string(off) + ")");
  }
  off = c.offset();
  p.counts.components = c.varint("component count");
  if (p.counts.components > p.counts.faces) format_error("more components than faces", off);
  off = c.offset();
  p.counts.unreferenced = c.varint("unreferenced vertex count");
  if (p.counts.unreferenced > p.counts.vertices)
    format_error("more unreferenced vertices than vertices", off);
  off = c.offset();
  if (c.u8("counts flags") != 0) format_error("reserved counts flag bits are set (must be zero)", off);
  if (c.left() != 0)
    format_error("counts section has " + std::to_string(c.left()) + " unexpected bytes", c.offset());

  // What the content can hold, checked before anything is allocated (docs/hardening.md), so a tiny
  // file cannot make the decoder reserve memory for a huge declared mesh. Every component has a quad
  // (4 vertices). Every vertex costs at least 3 adaptive binary decisions in the geometry section (per
  // axis at least one residual-length decision, or a repeat flag) and no decision costs less than
  // ~0.00156 bits (log2(65536 / 65465), a little less through the coder's truncation), so a geometry
  // section of B bytes holds at most ~1712 * (B + 4) vertices (a stream may leave out 4 zero bytes).
  if (p.counts.components > (p.counts.vertices - p.counts.unreferenced) / 4) {
    format_error("more components than the referenced vertices allow (4 each)", cs.payload_offset);
  }
  constexpr std::uint64_t kMaxVerticesPerGeometryByte = 2048;
  if (p.counts.vertices > kMaxVerticesPerGeometryByte * (p.geometry->payload.size() + 8)) {
    format_error("counts section declares " + std::to_string(p.counts.vertices) + " vertices but the " +
                     std::to_string(p.geometry->payload.size()) + "-byte geometry section cannot hold them",
                 p.geometry->payload_offset);
  }
  return p;
}

// Topology codes -> component partitions, with the vertex and face totals checked against the declared
// counts before any grid is built (so memory stays bounded by what the header declared).
void decode_components(Parsed& p) {
  const std::uint64_t f = p.counts.faces;
  // A schematic edge is a path of >= 1 mesh edges, and a mesh has at most 4 * faces edges.
  p.codes = decode_topology(p.topology->payload, p.topology->payload_offset, p.counts.components, 4 * f,
                            std::max<std::uint64_t>(4 * f, 1));
  std::uint64_t vertices = 0, faces = 0;
  const std::uint64_t off = p.topology->payload_offset;
  for (const TopologyCode& code : p.codes) {
    ComponentPartition part;
    try {
      part = partition_from_code(code);
    } catch (const Error& e) {
      if (e.code() != ErrorCode::kFormat) throw;
      format_error(std::string(e.what()) + " in component " + std::to_string(p.parts.size()) +
                       " of the topology section",
                   off);
    }
    std::uint64_t cv = 0, cf = 0;
    if (part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus) {
      cf = std::uint64_t{part.a} * part.b;
      cv = part.kind == ComponentKind::kAnnulus ? std::uint64_t{part.a} * (part.b + 1) : cf;
    } else {
      const Schematic& s = part.schematic;
      cv = s.vertex_count;
      for (std::uint32_t e = 0; e < s.edge_count(); ++e) cv += s.edge_length[e] - 1;
      for (std::uint32_t pf = 0; pf < s.face_count(); ++pf) {
        if (s.face_hole[pf]) continue;
        PatchSize ps = patch_size(s, pf);
        cf += std::uint64_t{ps.a} * ps.b;
        cv += std::uint64_t{ps.a - 1} * (ps.b - 1);
        if (cf > f) break;
      }
    }
    vertices += cv;
    faces += cf;
    if (faces > f || vertices > p.counts.vertices - p.counts.unreferenced) {
      format_error("topology describes more faces or vertices than the counts section declares", off);
    }
    p.comp_vertices.push_back(static_cast<std::uint32_t>(cv));
    p.comp_faces.push_back(static_cast<std::uint32_t>(cf));
    p.parts.push_back(std::move(part));
  }
  if (faces != f || vertices != p.counts.vertices - p.counts.unreferenced) {
    format_error("topology describes " + std::to_string(faces) + " faces and " + std::to_string(vertices) +
                     " referenced vertices, the counts section " + std::to_string(f) + " and " +
                     std::to_string(p.counts.vertices - p.counts.unreferenced),
                 off);
  }
}

// Below this many faces the decoder checks its quads on its own thread: starting one would cost more.
constexpr std::uint32_t kCheckBesideFrom = 4096;

// The adjacency of the rebuilt quads. The checks on each schematic do not rule out every layout that
// glues into something other than a manifold, consistently oriented quad mesh (a patch ring through
// one vertex twice, say), so the quads are checked as an encoder's input is: what build_adjacency
// refuses is a format error at the topology section (`offset`), and a file never decodes to what no
// encoder wrote.
Adjacency rebuilt_adjacency(std::span<const std::uint32_t> quads, std::uint32_t vertex_count,
                            std::uint64_t offset) {
  try {
    return build_adjacency(quads, vertex_count);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::kLimit || e.code() == ErrorCode::kInternal) throw;
    format_error(std::string("the topology does not describe a valid quad mesh: ") + e.what(), offset);
  }
}

// Positions in layout order from positions in coding order (patch order: coding position k holds
// layout vertex coding[k]).
std::vector<float> to_layout_order(std::vector<float> coded, const std::vector<std::uint32_t>& coding) {
  if (coding.empty()) return coded;
  std::vector<float> out(coded.size());
  for (std::size_t k = 0; k < coding.size(); ++k)
    std::copy_n(&coded[3 * k], 3, &out[3 * std::size_t{coding[k]}]);
  return out;
}

}  // namespace

namespace {

// The symmetry section, if the geometry section predicts by it: either both or neither (else a format
// error at the one there).
const Section* symmetry_section(const Parsed& p) {
  const std::uint8_t tools = geometry_tools(p.geometry->payload, p.geometry->payload_offset);
  const Section* symmetry = p.file.find(container::kTagSymmetry);
  if ((tools & geometry_tool::kMirror) && !symmetry)
    format_error("geometry section: mirror prediction without a symmetry section",
                 p.geometry->payload_offset);
  if (symmetry && !(tools & geometry_tool::kMirror))
    format_error("symmetry section: the geometry section does not predict by it", symmetry->offset);
  return symmetry;
}

// The layout of the decoded topology in the geometry section's coding order, its sizes checked.
MeshLayout lay_out(Parsed& p) {
  decode_components(p);
  const auto nv = static_cast<std::uint32_t>(p.counts.vertices);
  const auto nf = static_cast<std::uint32_t>(p.counts.faces);
  const std::uint8_t tools = geometry_tools(p.geometry->payload, p.geometry->payload_offset);
  const CodingOrder order = coding_order(tools);
  MeshLayout layout = assemble(p.parts, static_cast<std::uint32_t>(p.counts.unreferenced), order);
  if (layout.stencil.size() != nv || layout.quads.size() != 4 * std::size_t{nf} ||
      (order == CodingOrder::kPatch && layout.coding.size() != nv)) {
    throw Error(ErrorCode::kInternal, "decode: grid layout sizes disagree with the checked counts");
  }
  // Mirror prediction: each vertex's image under the symmetry section's mirror, as its stencil's source.
  if (const Section* symmetry = symmetry_section(p)) {
    p.adjacency = rebuilt_adjacency(layout.quads, nv, p.topology->payload_offset);
    MirrorMap mirror =
        section_mirror(symmetry->payload, symmetry->payload_offset, layout.quads, *p.adjacency);
    set_mirror_sources(layout.stencil, layout.coding, mirror);
    p.mirror = std::move(mirror.image);
  }
  return layout;
}

// The layout's adjacency, checked: lay_out's where it built it for the mirror (handed on once), else rebuilt.
Adjacency layout_adjacency(Parsed& p, std::span<const std::uint32_t> quads, std::uint32_t nv) {
  if (!p.adjacency) return rebuilt_adjacency(quads, nv, p.topology->payload_offset);
  Adjacency adj = std::move(*p.adjacency);
  p.adjacency.reset();
  return adj;
}

// The layout's quads and positions (layout order), the quads checked as rebuilt_adjacency does (their
// adjacency kept in `adjacency` if given).
QuadMesh decode_layout(Parsed& p, Adjacency* adjacency = nullptr) {
  MeshLayout layout = lay_out(p);
  const auto nv = static_cast<std::uint32_t>(p.counts.vertices);
  const auto nf = static_cast<std::uint32_t>(p.counts.faces);
  QuadMesh canonical;
  canonical.quads = std::move(layout.quads);
  // The check of the rebuilt quads (rebuilt_adjacency) needs no positions, so it runs beside the
  // geometry decoder (from kCheckBesideFrom faces), where lay_out has not made it for the mirror.
  auto check = [&quads = canonical.quads, nv, adjacency, &p] {
    Adjacency adj = layout_adjacency(p, quads, nv);
    if (adjacency) *adjacency = std::move(adj);
  };
  auto checked = beside(nf >= kCheckBesideFrom && !p.adjacency, check);  // else after the geometry
  canonical.positions = to_layout_order(
      decode_geometry(p.geometry->payload, p.geometry->payload_offset, layout.stencil, nv), layout.coding);
  checked.get();
  return canonical;
}

// The interior positions section's count (the spec, "Interior positions section"), checked.
std::uint64_t interior_count(const Section& s) {
  ByteReader r(s.payload, s.payload_offset, "interior positions section");
  const std::uint64_t n = r.varint("interior position count");
  if (n == 0) r.fail_at("no interior position", s.payload_offset);
  if (r.left() != 0) r.fail_at("bytes after the interior position count", r.offset());
  return n;
}

struct DecodedPolygons {
  PolygonFaces faces;
  std::vector<float> positions;
};

// A polygon mesh's faces and positions (canonical order) from its layout and polygons section: in a 3.12
// file with an interior positions section the geometry section codes the interior positions too, after
// the layout's, so the region stream is decoded first and gives their stencils.
DecodedPolygons decode_polygon_faces(Parsed& p, const Section& poly, const DecodeLimits& limits) {
  const Section* interior = p.file.find(container::kTagInterior);
  if (!interior) {
    Adjacency adj;
    const QuadMesh layout = decode_layout(p, &adj);
    PolygonStream stream =
        decode_polygon_stream(poly.payload, poly.payload_offset, layout.quads, adj, limits);
    std::vector<float> positions = polygon_positions(stream, adj.vertex_count, layout.positions, nullptr);
    return {std::move(stream.faces), std::move(positions)};
  }
  MeshLayout layout = lay_out(p);
  const auto nv = static_cast<std::uint32_t>(p.counts.vertices);
  const Adjacency adj = layout_adjacency(p, layout.quads, nv);
  PolygonStream stream = decode_polygon_stream(poly.payload, poly.payload_offset, layout.quads, adj, limits);
  const std::uint64_t n = interior_count(*interior);
  const std::uint64_t at = interior->payload_offset;
  std::vector<Stencil> stencil = interior_stencils(stream.faces, nv, layout.coding);
  if (n != stencil.size())
    format_error("interior positions section: " + std::to_string(n) +
                     " interior positions, and the polygons "
                     "section has " +
                     std::to_string(stencil.size()),
                 at);
  stencil.insert(stencil.begin(), layout.stencil.begin(), layout.stencil.end());
  std::vector<float> coded = decode_geometry(p.geometry->payload, p.geometry->payload_offset, stencil,
                                             nv + static_cast<std::uint32_t>(n));
  std::vector<float> interior_positions(coded.begin() + 3 * std::ptrdiff_t{nv}, coded.end());
  coded.resize(3 * std::size_t{nv});
  const std::vector<float> positions = to_layout_order(std::move(coded), layout.coding);
  std::vector<float> out = polygon_positions(stream, nv, positions, &interior_positions);
  return {std::move(stream.faces), std::move(out)};
}

// decode() after the parse.
QuadMesh decode_quads(Parsed& p) {
  QuadMesh canonical = decode_layout(p);
  if (!p.order) return canonical;
  const auto nv = static_cast<std::uint32_t>(p.counts.vertices);
  const auto nf = static_cast<std::uint32_t>(p.counts.faces);
  const OrderMap order_map = decode_order(p.order->payload, p.order->payload_offset, nv, nf);
  // The file's rotation r puts canonical corner c at input corner (c + r) % 4; permute's turns the
  // other way.
  std::vector<std::uint8_t> turn(nf);
  for (std::uint32_t f = 0; f < nf; ++f)
    turn[f] = static_cast<std::uint8_t>((4 - (order_map.rotation[f] & 3u)) & 3u);
  return permute(canonical, Renumbering{order_map.vertex, order_map.face, turn});
}

// A file of a newer minor version may use what this qsp still takes for reserved (as 3.9, 3.10 and 3.16
// gave flag bits a meaning): what it refuses in one is worded as a version error, upgrade qsp, not as a
// corrupt file ("Version").
template <typename Decode>
auto newer_minor_says_upgrade(std::string_view bytes, Decode&& decode) {
  try {
    return decode();
  } catch (const Error& e) {
    const bool ours = bytes.size() >= container::kFixedHeader &&
                      std::equal(std::begin(container::kMagic), std::end(container::kMagic), bytes.begin(),
                                 [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); });
    const auto minor = ours ? static_cast<std::uint8_t>(bytes[9]) : 0;
    if (e.code() != ErrorCode::kFormat || !ours || static_cast<std::uint8_t>(bytes[8]) != kFormatMajor ||
        minor <= kFormatMinor)
      throw;
    throw Error(ErrorCode::kVersion, "file is .qsp format 3." + std::to_string(minor) +
                                         ", newer than this qsp's 3." + std::to_string(kFormatMinor) +
                                         ", and reads as invalid here (" + e.what() + "; upgrade qsp)");
  }
}

QuadMesh decode_any_quads(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p = parse(bytes, limits);
  if (const Section* s = p.file.find(container::kTagPolygons))
    throw Error(ErrorCode::kNotQuad,
                "the file holds a polygon mesh (faces that are not quads, or a non-manifold or mis-oriented "
                "mesh: section 0x05 at byte offset " +
                    std::to_string(s->offset) + "), which this reader of quad meshes does not take");
  // The polygons section says the mesh itself is not a quad mesh; every other section a minor version
  // added holds data a quad mesh has no place for.
  for (const container::SectionKind& k : container::kSections) {
    const Section* s = container::holds_more_than_quads(k) ? p.file.find(k.tag) : nullptr;
    if (s)
      throw Error(ErrorCode::kNotQuad,
                  "the file holds " + std::string(k.name) + " (section " + container::tag_name(k.tag) +
                      " at byte offset " + std::to_string(s->offset) +
                      "), which this reader of quad meshes does not return: decode_polygons() reads them");
  }
  return decode_quads(p);
}

PolygonMesh decode_any_polygons(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p = parse(bytes, limits);
  const Section* poly = p.file.find(container::kTagPolygons);
  const Section* uv = p.file.find(container::kTagTexcoords);
  const Section* labels = p.file.find(container::kTagLabels);
  const Section* tags = p.file.find(container::kTagTags);
  const Section* normals = p.file.find(container::kTagNormals);
  const Section* exact = p.file.find(container::kTagExact);
  const Section* kept = p.file.find(container::kTagKeptLines);
  const Section* colors = p.file.find(container::kTagColors);
  const Section* statements = p.file.find(container::kTagStatements);
  const Section* exact_values = p.file.find(container::kTagExactValues);
  const Section* properties = p.file.find(container::kTagProperties);
  const Section* ply_info = p.file.find(container::kTagPlyInfo);
  if (const Section* interior = p.file.find(container::kTagInterior); interior && !poly)
    format_error("interior positions section without a polygons section", interior->offset);
  if (!poly && !uv && !labels && !tags && !normals && !exact && !kept && !colors && !statements &&
      !exact_values && !properties && !ply_info)
    return polygon_mesh(decode_quads(p));
  // The exact values and the statement order describe the mesh as returned (after any order section).
  const auto with_statements = [&](PolygonMesh m) {
    if (exact_values) {
      const ExactArray arrays[] = {
          {m.texcoords, {}, m.texcoord_components, "texture coordinates", "texture coordinate"},
          {m.normals, {}, 3, "normals", "normal"},
          {m.vertex_colors, {}, m.vertex_color_components, "vertex colours", "vertex colour"},
          {m.face_colors, {}, m.face_color_components, "face colours", "face colour"}};
      std::vector<std::vector<double>> v =
          decode_exact_values_section(exact_values->payload, exact_values->payload_offset, arrays);
      m.texcoords64 = std::move(v[0]);
      m.normals64 = std::move(v[1]);
      m.vertex_colors64 = std::move(v[2]);
      m.face_colors64 = std::move(v[3]);
    }
    if (statements)
      m.statements = decode_statements_section(statements->payload, statements->payload_offset, m);
    return m;
  };
  // The output mesh in canonical order, then its texture coordinates, then the input's numbering.
  PolygonMesh out;
  std::uint32_t nv = 0;
  if (poly) {
    DecodedPolygons d = decode_polygon_faces(p, *poly, limits);
    nv = d.faces.vertex_count;
    out.positions = std::move(d.positions);
    out.face_offsets = std::move(d.faces.face_offsets);
    out.corners = std::move(d.faces.corners);
  } else {
    out = polygon_mesh(decode_layout(p));
    nv = static_cast<std::uint32_t>(p.counts.vertices);
  }
  if (kept) out.kept_lines = decode_kept_lines_section(kept->payload, kept->payload_offset);
  if (ply_info) out.ply_info = decode_ply_info_section(ply_info->payload, ply_info->payload_offset);
  if (exact) {
    if (geometry_quantize_bits(p.geometry->payload, p.geometry->payload_offset) != 0)
      throw Error(ErrorCode::kFormat, "exact positions section: the geometry is quantized (at byte offset " +
                                          std::to_string(exact->payload_offset) + ")");
    out.positions64 = decode_exact_section(exact->payload, exact->payload_offset, out.positions);
  }
  if (uv) {
    DecodedTexcoords t = decode_texcoords_section(
        uv->payload, uv->payload_offset, out.face_offsets, out.corners, nv, out.positions, p.order != nullptr,
        limits, kTexcoordWords, p.file.minor, poly ? std::span<const std::uint32_t>() : p.mirror);
    out.texcoord_components = t.components;
    out.texcoords = std::move(t.values);
    out.corner_texcoords = std::move(t.corners);
  }
  if (normals) {
    DecodedTexcoords n =
        decode_texcoords_section(normals->payload, normals->payload_offset, out.face_offsets, out.corners, nv,
                                 out.positions, p.order != nullptr, limits, kNormalWords, p.file.minor);
    out.normals = std::move(n.values);
    out.corner_normals = std::move(n.corners);
  }
  if (colors) {
    DecodedColors c =
        decode_colors_section(colors->payload, colors->payload_offset, out.face_offsets, out.corners, nv);
    out.vertex_color_components = c.vertex_components;
    out.vertex_colors = std::move(c.vertex);
    out.face_color_components = c.face_components;
    out.face_colors = std::move(c.face);
  }
  if (properties) {
    DecodedProperties d =
        decode_properties_section(properties->payload, properties->payload_offset, nv, out.face_count());
    out.vertex_properties = std::move(d.vertex);
    out.face_properties = std::move(d.face);
  }
  if (labels) {
    DecodedLabels l = decode_labels_section(labels->payload, labels->payload_offset,
                                            static_cast<std::uint32_t>(out.face_count()), p.file.minor);
    out.objects = std::move(l.objects);
    out.groups = std::move(l.groups);
    out.materials = std::move(l.materials);
    out.smoothing = std::move(l.smoothing);
    out.material_libraries = std::move(l.material_libraries);
  }
  // Tags index the output as it is returned: the order section does not change them.
  if (tags)
    out.tags = decode_tags_section(tags->payload, tags->payload_offset, out.vertex_count(), out.face_count(),
                                   p.order != nullptr);
  if (!p.order) return with_statements(std::move(out));
  // The input's numbering: vertex j is output vertex vertex[j]; face f is output face face[f], its corner
  // (i + rotation[f]) mod d output corner i.
  const std::vector<std::uint32_t>& fo = out.face_offsets;
  const auto nf = static_cast<std::uint32_t>(fo.size() - 1);
  std::vector<std::uint32_t> degree(nf);
  for (std::uint32_t f = 0; f < nf; ++f) degree[f] = fo[f + 1] - fo[f];
  PolygonOrder order;
  if (poly) {
    order = decode_polygon_order(p.order->payload, p.order->payload_offset, nv, degree);
  } else {
    OrderMap quads = decode_order(p.order->payload, p.order->payload_offset, nv, nf);
    order.vertex = std::move(quads.vertex);
    order.face = std::move(quads.face);
    order.rotation.assign(quads.rotation.begin(), quads.rotation.end());
  }
  // Output corner i is the input face's corner (i + rotation) mod d: the input's corner c is output corner
  // (c - rotation) mod d. Tags already index the input's numbering.
  std::vector<std::uint32_t> first(nf);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t d = degree[order.face[f]];
    first[f] = (d - order.rotation[f] % d) % d;
  }
  PolygonRenumbering r;
  r.vertex_from = order.vertex;
  r.face_from = order.face;
  r.first = first;
  r.renumber_tags = false;
  return with_statements(permute(out, r));
}

}  // namespace

QuadMesh decode(std::string_view bytes, const DecodeLimits& limits) {
  return newer_minor_says_upgrade(bytes, [&] { return decode_any_quads(bytes, limits); });
}

PolygonMesh decode_polygons(std::string_view bytes, const DecodeLimits& limits) {
  return newer_minor_says_upgrade(bytes, [&] { return decode_any_polygons(bytes, limits); });
}

bool holds_polygons(std::string_view bytes) {
  const container::File f = container::parse(bytes);
  return std::any_of(std::begin(container::kSections), std::end(container::kSections),
                     [&](const container::SectionKind& k) {
                       return container::holds_more_than_quads(k) && f.find(k.tag) != nullptr;
                     }) ||
         f.find(container::kTagKeptLines) != nullptr || f.find(container::kTagStatements) != nullptr ||
         f.find(container::kTagPlyInfo) != nullptr;
}

FileTopology file_topology(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p = parse(bytes, limits);
  decode_components(p);
  return {std::move(p.codes), p.counts.unreferenced};
}

OrderMap file_order(std::string_view bytes, const DecodeLimits& limits) {
  const Parsed p = parse(bytes, limits);
  if (!p.order) return {};
  if (p.file.find(container::kTagPolygons))
    throw Error(ErrorCode::kNotQuad,
                "the file holds a polygon mesh, whose order section is not a quad mesh's");
  return decode_order(p.order->payload, p.order->payload_offset,
                      static_cast<std::uint32_t>(p.counts.vertices),
                      static_cast<std::uint32_t>(p.counts.faces));
}

namespace {

// The polygons section's bytes: its counts and region stream are connectivity, the interior positions
// after them geometry (the spec, "Polygons section"; the section was checked by parse()).
void split_polygons_section(const Section& s, FileInfo& info) {
  ByteReader r(s.payload, s.payload_offset, "polygons section");
  for (const char* what : {"interior vertex count", "region count", "glue group count"}) (void)r.varint(what);
  (void)r.take(r.varint("stream length"), "region stream");
  info.polygon_positions_bytes = r.left();
  info.polygon_connectivity_bytes = s.size() - r.left();
  info.connectivity_bytes += info.polygon_connectivity_bytes;
  info.geometry_bytes += info.polygon_positions_bytes;
}

// The exact values section's bytes, each block (and its length) with its kind's: texture coordinates,
// normals, colours; the section's own tag, length and kinds byte with the first kind it holds.
void split_exact_values_section(const Section& s, FileInfo& info) {
  std::uint64_t* kind_bytes[] = {&info.texcoord_bytes, &info.normal_bytes, &info.color_bytes,
                                 &info.color_bytes};
  ByteReader r(s.payload, s.payload_offset, "exact values section");
  const std::uint8_t kinds = r.u8("kinds");
  std::uint64_t head = s.size() - s.payload.size() + 1;
  for (std::size_t k = 0; k < 4; ++k) {
    if (!(kinds >> k & 1u)) continue;
    const std::size_t at = r.pos();
    (void)r.take(r.varint("block length"), "block");
    *kind_bytes[k] += r.pos() - at + head;
    head = 0;
  }
  if (head) info.other_bytes += s.size();  // no kind (a section parse() let through): counted as other
}

}  // namespace

FileInfo inspect(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p = parse(bytes, limits);
  decode_components(p);
  FileInfo info;
  info.version_major = p.file.major;
  info.version_minor = p.file.minor;
  info.level = p.file.level;
  info.total_bytes = bytes.size();
  info.vertices = p.counts.vertices;
  info.faces = p.counts.faces;
  info.unreferenced = p.counts.unreferenced;
  info.keep_order = p.order != nullptr;
  info.polygons = p.file.find(container::kTagPolygons) != nullptr;
  info.geometry_tools = geometry_tools(p.geometry->payload, p.geometry->payload_offset);
  info.geometry_order = coding_order(info.geometry_tools);
  info.quantize_bits = geometry_quantize_bits(p.geometry->payload, p.geometry->payload_offset);
  const Section* symmetry = symmetry_section(p);
  std::uint64_t in_sections = 0;
  for (const Section& s : p.file.sections) {
    const std::uint64_t size = s.size();
    in_sections += size;
    info.sections.push_back({s.tag, s.offset, size});
    if (s.tag == container::kTagCounts || s.tag == container::kTagTopology)
      info.connectivity_bytes += size;
    else if (s.tag == container::kTagGeometry || s.tag == container::kTagSymmetry)
      info.geometry_bytes += size;  // the symmetry section says how the positions are predicted
    else if (s.tag == container::kTagInterior)
      info.geometry_bytes += size, info.interior_positions = interior_count(s);
    else if (s.tag == container::kTagOrder || s.tag == container::kTagStatements)
      info.order_bytes += size;
    else if (s.tag == container::kTagPolygons)
      split_polygons_section(s, info);
    else if (s.tag == container::kTagTexcoords)
      info.texcoord_bytes += size;
    else if (s.tag == container::kTagLabels)
      info.label_bytes += size;
    else if (s.tag == container::kTagTags)
      info.tag_bytes += size;
    else if (s.tag == container::kTagNormals)
      info.normal_bytes += size;
    else if (s.tag == container::kTagExact)
      info.exact_bytes += size;
    else if (s.tag == container::kTagColors)
      info.color_bytes += size;
    else if (s.tag == container::kTagExactValues)
      split_exact_values_section(s, info);
    else if (s.tag == container::kTagProperties)
      info.property_bytes += size;
    else if (s.tag == container::kTagComments || s.tag == container::kTagCodedComments)
      info.comment_bytes += size;
    else if (s.tag == container::kTagKeptLines || s.tag == container::kTagPlyInfo)
      info.kept_line_bytes += size;
    else
      info.other_bytes += size;
  }
  info.header_bytes = info.total_bytes - in_sections;
  for (std::size_t i = 0; i < p.parts.size(); ++i) {
    const ComponentPartition& part = p.parts[i];
    ComponentSummary cs;
    cs.kind = part.kind;
    cs.vertices = p.comp_vertices[i];
    cs.faces = p.comp_faces[i];
    cs.a = part.a;
    cs.b = part.b;
    cs.twist = part.twist;
    if (part.kind == ComponentKind::kUnstructured || part.kind == ComponentKind::kDisk) {
      cs.schematic_vertices = part.schematic.vertex_count;
      cs.schematic_edges = part.schematic.edge_count();
      cs.patches = part.schematic.patch_count();
    }
    info.schematic_vertices += cs.schematic_vertices;
    info.schematic_edges += cs.schematic_edges;
    info.patches += cs.patches;
    ++info.kind_counts[static_cast<std::size_t>(part.kind) & 3u];
    info.components.push_back(cs);
  }
  // Mesh edges and extraordinary vertices come from the rebuilt connectivity (positions not needed).
  const MeshLayout layout =
      assemble(p.parts, static_cast<std::uint32_t>(p.counts.unreferenced), std::nullopt);
  const Adjacency adj = rebuilt_adjacency(layout.quads, layout.vertex_count, p.topology->payload_offset);
  if (symmetry)  // as the decoder refuses it
    (void)section_mirror(symmetry->payload, symmetry->payload_offset, layout.quads, adj);
  info.edges = adj.halfedge_count() / 2;
  info.extraordinary = extraordinary_vertices(adj).size();
  return info;
}

}  // namespace qsp
