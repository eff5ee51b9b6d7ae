// The .qsp container (format-spec/qsp_format.md): header, tagged sections, checksum; and encode /
// decode / inspect on top of the partition, canonical, topology, geometry and order stages.
#include "qsp/codec.h"

// Header-only (XXH_INLINE_ALL): the installed library needs no xxhash to link against.
#define XXH_INLINE_ALL
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "qsp/error.h"
#include "qsp/geometry.h"

namespace qsp {
namespace {

constexpr unsigned char kMagic[8] = {0x89, 'Q', 'S', 'P', 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::size_t kChecksumBytes = 8;

// Section tags. Bit 7 set = optional: a decoder that does not know the tag skips the section.
constexpr std::uint8_t kTagCounts = 0x01;
constexpr std::uint8_t kTagTopology = 0x02;
constexpr std::uint8_t kTagGeometry = 0x03;
constexpr std::uint8_t kTagOrder = 0x04;
constexpr std::uint8_t kOptionalBit = 0x80;

// Hard limits of format version 1 (independent of DecodeLimits): indices are 32-bit, and the
// half-edge structure needs 4 * faces + boundary half-edges < 2^32.
constexpr std::uint64_t kFormatMaxVertices = 0xFFFFFFFEull;
constexpr std::uint64_t kFormatMaxFaces = (std::uint64_t{1} << 30) - 1;

std::string at(std::uint64_t offset) { return " (at byte offset " + std::to_string(offset) + ")"; }

[[noreturn]] void format_error(const std::string& what, std::uint64_t offset) {
  throw Error(ErrorCode::kFormat, what + at(offset));
}

void put_varint(std::string& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>(static_cast<std::uint8_t>(v) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}

std::size_t varint_size(std::uint64_t v) {
  std::size_t n = 1;
  while (v >= 0x80) {
    v >>= 7;
    ++n;
  }
  return n;
}

// Bounds-checked reader over the whole file; offsets in errors are absolute.
class Reader {
 public:
  Reader(std::string_view bytes, std::size_t pos, std::size_t end) : bytes_(bytes), pos_(pos), end_(end) {}
  std::size_t pos() const { return pos_; }
  std::size_t left() const { return end_ - pos_; }
  std::uint8_t u8(const char* what) {
    if (pos_ >= end_) format_error(std::string("truncated: no room for ") + what, pos_);
    return static_cast<std::uint8_t>(bytes_[pos_++]);
  }
  // LEB128, at most 10 bytes, minimal (no redundant trailing zero groups) so every value has one form.
  std::uint64_t varint(const char* what) {
    std::size_t start = pos_;
    std::uint64_t v = 0;
    for (unsigned shift = 0;; shift += 7) {
      std::uint8_t b = u8(what);
      if (shift == 63 && b > 1) format_error(std::string(what) + " does not fit in 64 bits", start);
      v |= std::uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) {
        if (b == 0 && shift != 0) format_error(std::string(what) + " is not minimally encoded", start);
        return v;
      }
    }
  }
  std::string_view take(std::uint64_t n, const char* what) {
    if (n > left()) {
      format_error(std::string(what) + " declares " + std::to_string(n) + " bytes but only " +
                       std::to_string(left()) + " remain",
                   pos_);
    }
    std::string_view s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }

 private:
  std::string_view bytes_;
  std::size_t pos_, end_;
};

struct Section {
  std::uint8_t tag = 0;
  std::uint64_t offset = 0;          // of the tag
  std::uint64_t payload_offset = 0;  // of the payload
  std::string_view payload;
};

struct Counts {
  std::uint64_t vertices = 0, faces = 0, components = 0, unreferenced = 0;
};

// Everything up to (not including) geometry decoding: what decode() and inspect() share.
struct Parsed {
  std::uint8_t major = 0, minor = 0;
  Counts counts;
  std::vector<Section> sections;
  std::optional<Section> topology, geometry, order;
  std::vector<TopologyCode> codes;
  std::vector<ComponentPartition> parts;
  std::vector<std::uint32_t> comp_vertices, comp_faces;
};

// Checks magic, version, declared size, checksum (in this order, so each failure gets the error that
// explains it best), then splits the sections. Returns the offset where sections start.
Parsed parse_container(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p;
  const std::size_t n = bytes.size();
  std::size_t magic_len = std::min<std::size_t>(n, 8);
  if (std::memcmp(bytes.data(), kMagic, magic_len) != 0) {
    std::string why = "not a .qsp file (bad magic number)";
    if (n >= 6 && static_cast<std::uint8_t>(bytes[0]) == 0x09 && bytes.substr(1, 3) == "QSP") {
      why += "; the high bit of byte 0 was cleared, as by a 7-bit transfer";
    } else if (n >= 6 && static_cast<std::uint8_t>(bytes[0]) == 0x89 && bytes.substr(1, 3) == "QSP") {
      why += "; the line-ending bytes were changed, as by a text-mode transfer or CR LF conversion";
    }
    format_error(why, 0);
  }
  if (n < 8) format_error("truncated: file ends inside the magic number", n);
  Reader r(bytes, 8, n);
  p.major = r.u8("version");
  p.minor = r.u8("version");
  if (p.major < kOldestMajor || p.major > kFormatMajor) {
    throw Error(ErrorCode::kVersion, "file is .qsp format " + std::to_string(p.major) + "." +
                                         std::to_string(p.minor) + "; this qsp reads formats " +
                                         std::to_string(kOldestMajor) + ".x to " +
                                         std::to_string(kFormatMajor) + ".x" +
                                         (p.major > kFormatMajor ? " (upgrade qsp)" : "") + at(8));
  }
  std::uint8_t flags = r.u8("header flags");
  std::uint64_t declared = r.varint("file size");
  if (declared > n) {
    format_error(
        "truncated: header declares " + std::to_string(declared) + " bytes, file has " + std::to_string(n),
        n);
  }
  if (declared < n)
    format_error(std::to_string(n - declared) + " trailing bytes after the end of the .qsp", declared);
  if (n < r.pos() + kChecksumBytes) format_error("truncated: no room for the checksum", n);
  const std::size_t body_end = n - kChecksumBytes;
  std::uint64_t stored = 0;
  for (std::size_t i = 0; i < kChecksumBytes; ++i) {
    stored |= std::uint64_t{static_cast<std::uint8_t>(bytes[body_end + i])} << (8 * i);
  }
  std::uint64_t actual = XXH64(bytes.data(), body_end, 0);
  if (stored != actual) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "checksum mismatch: stored %016llx, computed %016llx",
                  static_cast<unsigned long long>(stored), static_cast<unsigned long long>(actual));
    throw Error(ErrorCode::kChecksum, std::string(buf) + " (file is corrupt)" + at(body_end));
  }
  if (flags != 0) format_error("reserved header flag bits are set (must be zero)", 10);

  // Sections.
  Reader s(bytes, r.pos(), body_end);
  const std::uint8_t required_order[] = {kTagCounts, kTagTopology, kTagGeometry, kTagOrder};
  std::size_t next_required = 0;
  while (s.left() > 0) {
    Section sec;
    sec.offset = s.pos();
    sec.tag = s.u8("section tag");
    std::uint64_t len = s.varint("section length");
    sec.payload_offset = s.pos();
    sec.payload = s.take(len, "section");
    if (sec.tag & kOptionalBit) {
      p.sections.push_back(sec);  // optional: none defined yet (1.1), skipped
      continue;
    }
    std::size_t k = next_required;
    while (k < std::size(required_order) && required_order[k] != sec.tag) ++k;
    if (k == std::size(required_order)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "unknown or out-of-order required section tag 0x%02x", sec.tag);
      format_error(buf, sec.offset);
    }
    if (k > next_required && next_required < 3) {
      format_error("required section " + std::to_string(required_order[next_required]) + " is missing",
                   sec.offset);
    }
    next_required = k + 1;
    p.sections.push_back(sec);
  }
  if (next_required < 3)
    format_error("required section " + std::to_string(required_order[next_required]) + " is missing",
                 body_end);
  for (const Section& sec : p.sections) {
    if (sec.tag == kTagTopology) p.topology = sec;
    if (sec.tag == kTagGeometry) p.geometry = sec;
    if (sec.tag == kTagOrder) p.order = sec;
  }

  // Counts: checked against the format and the caller's limits before anything is allocated.
  const Section& cs = *std::find_if(p.sections.begin(), p.sections.end(),
                                    [](const Section& x) { return x.tag == kTagCounts; });
  Reader c(bytes, cs.payload_offset, cs.payload_offset + cs.payload.size());
  std::size_t off = c.pos();
  p.counts.vertices = c.varint("vertex count");
  if (p.counts.vertices > kFormatMaxVertices) format_error("vertex count exceeds the format's 2^32 - 2", off);
  if (p.counts.vertices > limits.max_vertices) {
    throw Error(ErrorCode::kLimit, "vertex count " + std::to_string(p.counts.vertices) +
                                       " exceeds the limit " + std::to_string(limits.max_vertices) + at(off));
  }
  off = c.pos();
  p.counts.faces = c.varint("face count");
  if (p.counts.faces > kFormatMaxFaces) format_error("face count exceeds the format's 2^30 - 1", off);
  if (p.counts.faces > limits.max_faces) {
    throw Error(ErrorCode::kLimit, "face count " + std::to_string(p.counts.faces) + " exceeds the limit " +
                                       std::to_string(limits.max_faces) + at(off));
  }
  off = c.pos();
  p.counts.components = c.varint("component count");
  if (p.counts.components > p.counts.faces) format_error("more components than faces", off);
  off = c.pos();
  p.counts.unreferenced = c.varint("unreferenced vertex count");
  if (p.counts.unreferenced > p.counts.vertices)
    format_error("more unreferenced vertices than vertices", off);
  off = c.pos();
  if (c.u8("counts flags") != 0) format_error("reserved counts flag bits are set (must be zero)", off);
  if (c.left() != 0)
    format_error("counts section has " + std::to_string(c.left()) + " unexpected bytes", c.pos());

  // What the content can hold, checked before anything is allocated (docs/hardening.md), so a tiny
  // file cannot make the decoder reserve memory for a huge declared mesh. Every component has a quad
  // (4 vertices). Every vertex costs at least 3 adaptive binary decisions in the geometry section (per
  // axis at least one residual-length decision, or a repeat flag) and no decision costs less than
  // ~0.00156 bits (log2(65536 / 65465), a little less through the coder's truncation), so a geometry
  // section of B bytes holds at most ~1712 * (B + 4) vertices (revision 4-6 streams may leave out 4 zero
  // bytes).
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

// How the topology and order streams end: compact from format 2.0, LZMA's in 1.x.
StreamEnds stream_ends(const Parsed& p) { return p.major >= 2 ? StreamEnds::kCompact : StreamEnds::kLzma; }

// Topology codes -> component partitions, with the vertex and face totals checked against the declared
// counts before any grid is built (so memory stays bounded by what the header declared).
void decode_components(Parsed& p) {
  const std::uint64_t f = p.counts.faces;
  // A schematic edge is a path of >= 1 mesh edges, and a mesh has at most 4 * faces edges.
  p.codes = decode_topology(p.topology->payload, p.topology->payload_offset, p.counts.components, 4 * f,
                            std::max<std::uint64_t>(4 * f, 1), stream_ends(p));
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

// Canonical quads and the stencils of all components, offset into one vertex numbering; unreferenced
// vertices at the end predict from the previous vertex. With CodingOrder::kPatch, `coding` gets the
// canonical vertex at each coding position (the stencils index coding positions).
void assemble(const std::vector<ComponentPartition>& parts, std::uint32_t unreferenced, CodingOrder order,
              std::vector<std::uint32_t>& quads, std::vector<GridLayout::Stencil>& stencil,
              std::vector<std::uint32_t>* coding = nullptr) {
  auto shift = [](std::uint32_t v, std::uint32_t base) { return v == kInvalid ? kInvalid : v + base; };
  const bool patch = order == CodingOrder::kPatch;
  if (patch && coding) coding->clear();
  for (const ComponentPartition& part : parts) {
    GridLayout g = grid_layout(part, order);
    auto base = static_cast<std::uint32_t>(stencil.size());
    if (patch && coding) {
      if (g.coding.empty()) {
        for (std::uint32_t v = 0; v < g.vertex_count; ++v) coding->push_back(v + base);
      } else {
        for (std::uint32_t v : g.coding) coding->push_back(v + base);
      }
    }
    if (base == 0 && quads.empty()) {  // the first component needs no shift: move, not copy (peak memory)
      quads = std::move(g.quads);
      stencil = std::move(g.stencil);
      continue;
    }
    for (std::uint32_t v : g.quads) quads.push_back(v + base);
    for (GridLayout::Stencil st : g.stencil) {
      for (std::uint32_t* j : st.vertex_fields()) *j = shift(*j, base);
      stencil.push_back(st);
    }
  }
  for (std::uint32_t u = 0; u < unreferenced; ++u) {
    auto v = static_cast<std::uint32_t>(stencil.size());
    stencil.push_back({v == 0 ? kInvalid : v - 1, kInvalid, kInvalid, kInvalid});
    if (patch && coding) coding->push_back(v);
  }
}

void put_section(std::string& out, std::uint8_t tag, std::string_view payload) {
  out.push_back(static_cast<char>(tag));
  put_varint(out, payload.size());
  out.append(payload);
}

// The geometry header choice (value repeats, decimal grid or float bits) that the encodes of one mesh
// share. Which header is smallest depends on the coordinates, hardly on the partition or the coding
// order, so only the first encode tries them all; on the 23 shared meshes, lossless and at 14 bits,
// the files are byte-identical to trying every header everywhere. Small meshes then run 7 geometry
// encodes at 14 bits and 9 lossless, not 12 and 24 (plus the normal-chaining trials).
struct SharedChoice {
  std::promise<GeometryChoice> chosen;  // set once, by the encode that chooses (or its failure)
  std::shared_future<GeometryChoice> future = chosen.get_future().share();
  bool set = false;
};

// How one encode_partition takes part: the one that chooses publishes its choice, the others wait for
// it (each with its own copy of the future, as threads must); without one, the encode chooses alone
// and reuses its choice for its second coding order.
struct ChoiceRole {
  SharedChoice* publish = nullptr;
  std::optional<std::shared_future<GeometryChoice>> wait;
};

// The file for `mesh` stored with `partition` (of `adj`, its adjacency).
std::string encode_partition(const QuadMesh& mesh, const Adjacency& adj, const Partition& partition,
                             const EncodeOptions& options, const Effort& effort, OrderMap* order_out,
                             ChoiceRole role = {}) {
  const std::uint64_t nv = mesh.vertex_count(), nf = mesh.face_count();
  CanonicalMesh cm = canonicalize(mesh, adj, partition);

  // Canonical numbering of the input, checked to be a bijection that maps every layout quad onto an
  // input quad (rotated): the decoder rebuilds exactly these quads, so the file cannot lie.
  std::vector<TopologyCode> codes;
  std::vector<ComponentPartition> parts;
  OrderMap order;
  order.vertex.assign(nv, kInvalid);
  order.face.assign(nf, kInvalid);
  order.rotation.assign(nf, 0);
  std::uint32_t vbase = 0, fbase = 0;
  auto internal = [](const std::string& why) { throw Error(ErrorCode::kInternal, "encode: " + why); };
  for (const CanonicalComponent& cc : cm.components) {
    codes.push_back(cc.code);
    parts.push_back(cc.part);
    for (std::size_t i = 0; i < cc.map.vertex.size(); ++i) {
      std::uint32_t v = cc.map.vertex[i];
      if (v >= nv || order.vertex[v] != kInvalid) internal("layout vertex map is not a bijection");
      order.vertex[v] = vbase + static_cast<std::uint32_t>(i);
    }
    for (std::size_t i = 0; i < cc.map.face.size(); ++i) {
      std::uint32_t f = cc.map.face[i];
      if (f >= nf || order.face[f] != kInvalid) internal("layout face map is not a bijection");
      order.face[f] = fbase + static_cast<std::uint32_t>(i);
      order.rotation[f] = cc.map.rotation[i] & 3u;
    }
    vbase += static_cast<std::uint32_t>(cc.map.vertex.size());
    fbase += static_cast<std::uint32_t>(cc.map.face.size());
  }
  for (std::uint32_t v : cm.unreferenced) {
    if (v >= nv || order.vertex[v] != kInvalid)
      internal("unreferenced vertex listed twice or also in a face");
    order.vertex[v] = vbase++;
  }
  if (vbase != nv || fbase != nf) internal("canonical form does not cover every vertex and face");

  const CodingOrder first = options.geometry_order.value_or(CodingOrder::kPatch);
  const auto unreferenced = static_cast<std::uint32_t>(cm.unreferenced.size());
  std::vector<std::uint32_t> quads, coding;
  std::vector<GridLayout::Stencil> stencil;
  assemble(parts, unreferenced, first, quads, stencil, &coding);
  if (quads.size() != mesh.quads.size() || stencil.size() != nv ||
      (first == CodingOrder::kPatch && coding.size() != nv))
    internal("layout sizes differ from the mesh");
  std::vector<std::uint32_t> canonical_to_input(nv);
  for (std::uint32_t v = 0; v < nv; ++v) canonical_to_input[order.vertex[v]] = v;
  for (std::uint32_t f = 0; f < nf; ++f) {
    std::uint32_t cf = order.face[f], r = order.rotation[f];
    for (std::uint32_t c = 0; c < 4; ++c) {
      if (canonical_to_input[quads[4 * cf + c]] != mesh.quads[4 * f + (c + r) % 4]) {
        internal("layout quad " + std::to_string(cf) + " does not match input face " + std::to_string(f));
      }
    }
  }
  quads = {};

  // Positions in coding order: canonical order, or for patch order canonical vertex coding[k] at k.
  auto coded_positions = [&](CodingOrder o) {
    std::vector<float> positions(3 * std::size_t{nv});
    for (std::uint32_t k = 0; k < nv; ++k) {
      const std::uint32_t v = canonical_to_input[o == CodingOrder::kPatch ? coding[k] : k];
      std::copy_n(&mesh.positions[3 * std::size_t{v}], 3, &positions[3 * std::size_t{k}]);
    }
    return positions;
  };
  GeometryOptions gopt;
  gopt.quantize_bits = options.quantize_bits;
  gopt.order = first;
  // Revision 6 where the level tries it (and keeps it only where smaller), unless the caller forces it.
  gopt.shapes = options.geometry_shapes;
  if (!gopt.shapes && !effort.try_shapes) gopt.shapes = false;
  gopt.header_sample = effort.header_sample;
  gopt.try_chaining = effort.try_chaining;
  gopt.repeats_must_pay = effort.repeats_must_pay;
  // One pipeline leaves the second core idle: give it the range coder from a smaller section than
  // geometry's own default, which assumes the partitions' pipelines keep both cores busy.
  constexpr std::uint64_t kCoderThreadAloneAbove = 8192;
  if (options.threads == 1) {
    gopt.coder_thread = false;
  } else if (!effort.all_partitions && nv > kCoderThreadAloneAbove) {
    gopt.coder_thread = true;
  }
  if (role.wait) gopt.choice = role.wait->get();  // rethrows what failed the encode that chooses
  GeometryChoice chosen;
  std::string geometry = encode_geometry(coded_positions(first), stencil, gopt, &chosen);
  gopt.choice = chosen;
  if (role.publish && !role.publish->set) {
    role.publish->chosen.set_value(chosen);
    role.publish->set = true;
  }
  if (!options.geometry_order && effort.both_orders) {
    stencil.clear();
    assemble(parts, unreferenced, CodingOrder::kLayout, quads, stencil);
    gopt.order = CodingOrder::kLayout;
    std::string layout = encode_geometry(coded_positions(CodingOrder::kLayout), stencil, gopt);
    if (layout.size() < geometry.size()) geometry = std::move(layout);
  }

  std::string counts;
  put_varint(counts, nv);
  put_varint(counts, nf);
  put_varint(counts, codes.size());
  put_varint(counts, cm.unreferenced.size());
  counts.push_back(0);  // flags: reserved

  std::string body;
  put_section(body, kTagCounts, counts);
  put_section(body, kTagTopology, encode_topology(codes));
  put_section(body, kTagGeometry, geometry);
  if (options.keep_order) put_section(body, kTagOrder, encode_order(order));

  // The file size field counts itself: find the varint length that is consistent.
  std::string out(reinterpret_cast<const char*>(kMagic), 8);
  out.push_back(static_cast<char>(kFormatMajor));
  out.push_back(static_cast<char>(kFormatMinor));
  out.push_back(0);  // header flags: reserved
  std::uint64_t total = out.size() + body.size() + kChecksumBytes + 1;
  while (out.size() + varint_size(total) + body.size() + kChecksumBytes != total) ++total;
  put_varint(out, total);
  out += body;
  std::uint64_t sum = XXH64(out.data(), out.size(), 0);
  for (std::size_t i = 0; i < kChecksumBytes; ++i)
    out.push_back(static_cast<char>(static_cast<std::uint8_t>(sum >> (8 * i))));
  if (order_out) *order_out = std::move(order);
  return out;
}

}  // namespace

std::string encode(const QuadMesh& mesh, const EncodeOptions& options, OrderMap* order_out) {
  const std::uint64_t nv = mesh.vertex_count(), nf = mesh.face_count();
  if (mesh.positions.size() % 3 != 0 || mesh.quads.size() % 4 != 0) {
    throw Error(ErrorCode::kUsage, "encode: positions or quads array has a partial element");
  }
  if (nv > kFormatMaxVertices) throw Error(ErrorCode::kLimit, "mesh has more than 2^32 - 2 vertices");
  if (nf > kFormatMaxFaces) throw Error(ErrorCode::kLimit, "mesh has more than 2^30 - 1 faces");
  const Effort effort = level_effort(options.level, nv);
  const Adjacency adj = build_adjacency(mesh);
  // Smaller partitions usually give smaller files (fewer schematic edges, longer patch rows), but not
  // always (mh_fedora, osd_catmark_car, igl_teddy at 14 bits): the highest levels try all three.
  if (options.partition || !effort.all_partitions) {
    const PartitionMode mode = options.partition.value_or(PartitionMode::kMotorcycle);
    return encode_partition(mesh, adj, qsp::partition(adj, mode, mesh.positions), options, effort, order_out);
  }
  // The three encodes are independent whole pipelines over read-only inputs: greedy runs on another
  // thread while this one does the motorcycle graph and merge (the heuristics take longer).
  struct Result {
    std::string bytes;
    OrderMap order;
  };
  auto run = [&](PartitionMode mode, ChoiceRole role) {
    Result r;
    r.bytes = encode_partition(mesh, adj, qsp::partition(adj, mode, mesh.positions), options, effort,
                               order_out ? &r.order : nullptr, std::move(role));
    return r;
  };
  // The motorcycle pipeline chooses the geometry header; the heuristics' pipelines wait for it.
  SharedChoice shared;
  // A heuristic's pipeline that trips an internal check only loses its candidacy (partition() already
  // falls back the same way for an invalid cut set): the motorcycle file is always there.
  auto candidate = [&](PartitionMode mode, ChoiceRole role) {
    try {
      return run(mode, std::move(role));
    } catch (const Error& e) {
      if (e.code() != ErrorCode::kInternal) throw;
      return Result{};
    }
  };
  const ChoiceRole waits{nullptr, shared.future};  // copied here, on this thread
  // Below ~1000 vertices the three take well under a millisecond each and starting a thread costs more
  // than it saves (much more under sanitizers: the fuzzers encode thousands of tiny meshes a second).
  constexpr std::uint64_t kThreadFrom = 1024;
  std::future<Result> greedy;
  if (nv >= kThreadFrom && options.threads != 1) {
    try {
      greedy = std::async(std::launch::async, candidate, PartitionMode::kGreedy, waits);
    } catch (const std::system_error&) {
      // no thread to be had: greedy runs below, on this one
    }
  }
  std::array<Result, 3> results;  // motorcycle, greedy, merge: the first smallest wins
  try {
    results[0] = run(PartitionMode::kMotorcycle, ChoiceRole{&shared, std::nullopt});
  } catch (...) {
    // Wake the waiting pipeline with the same failure; then the future's destructor waits for it.
    if (!shared.set) shared.chosen.set_exception(std::current_exception());
    throw;
  }
  results[2] = candidate(PartitionMode::kMerge, waits);
  results[1] = greedy.valid() ? greedy.get() : candidate(PartitionMode::kGreedy, waits);
  Result* best = &results[0];
  for (Result& r : results)
    if (!r.bytes.empty() && r.bytes.size() < best->bytes.size()) best = &r;
  if (order_out) *order_out = std::move(best->order);
  return std::move(best->bytes);
}

namespace {

// The geometry section's coding order (its revision byte, and in revisions 4-6 a flag), which the
// stencils must be built in.
CodingOrder coding_order_of(const Parsed& p) {
  try {
    return geometry_coding_order(p.geometry->payload);
  } catch (const Error& e) {
    format_error(std::string(e.what()) + " in the geometry section", p.geometry->payload_offset);
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

}  // namespace

QuadMesh decode(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p = parse_container(bytes, limits);
  decode_components(p);
  QuadMesh canonical;
  std::vector<GridLayout::Stencil> stencil;
  std::vector<std::uint32_t> coding;
  const CodingOrder corder = coding_order_of(p);
  assemble(p.parts, static_cast<std::uint32_t>(p.counts.unreferenced), corder, canonical.quads, stencil,
           &coding);
  const auto nv = static_cast<std::uint32_t>(p.counts.vertices);
  const auto nf = static_cast<std::uint32_t>(p.counts.faces);
  if (stencil.size() != nv || canonical.quads.size() != 4 * std::size_t{nf} ||
      (corder == CodingOrder::kPatch && coding.size() != nv)) {
    throw Error(ErrorCode::kInternal, "decode: grid layout sizes disagree with the checked counts");
  }
  // The check of the rebuilt quads (rebuilt_adjacency) needs no positions, so it runs beside the
  // geometry decoder (from kCheckBesideFrom faces). Its size limit is checked here, before decoding.
  if (nf >= kAdjacencyFaceLimit || nv >= kAdjacencyVertexLimit) {
    throw Error(ErrorCode::kLimit, "qsp rebuilds at most 2^29 - 1 faces and 2^31 - 1 vertices");
  }
  auto check = [&quads = canonical.quads, nv, offset = p.topology->payload_offset] {
    (void)rebuilt_adjacency(quads, nv, offset);
  };
  std::future<void> checked;
  if (nf >= kCheckBesideFrom) {
    try {
      checked = std::async(std::launch::async, check);
    } catch (const std::system_error&) {
      // no thread to be had: the check runs after the geometry, on this one
    }
  }
  try {
    canonical.positions = decode_geometry(p.geometry->payload, stencil, nv);
    if (corder == CodingOrder::kPatch) {
      std::vector<float> canonical_positions(canonical.positions.size());
      for (std::uint32_t k = 0; k < nv; ++k)
        std::copy_n(&canonical.positions[3 * std::size_t{k}], 3,
                    &canonical_positions[3 * std::size_t{coding[k]}]);
      canonical.positions = std::move(canonical_positions);
    }
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kFormat) throw;
    format_error(std::string(e.what()) + " in the geometry section", p.geometry->payload_offset);
  }
  if (canonical.positions.size() != 3 * std::size_t{nv}) {
    format_error("geometry section decodes to the wrong number of positions", p.geometry->payload_offset);
  }
  if (checked.valid()) {
    checked.get();
  } else {
    check();
  }
  if (!p.order) return canonical;

  OrderMap order = decode_order(p.order->payload, p.order->payload_offset, nv, nf, stream_ends(p));
  QuadMesh out;
  out.positions.resize(canonical.positions.size());
  out.quads.resize(canonical.quads.size());
  std::vector<std::uint32_t> canonical_to_input(nv);
  for (std::uint32_t v = 0; v < nv; ++v) {
    canonical_to_input[order.vertex[v]] = v;
    std::copy_n(&canonical.positions[3 * std::size_t{order.vertex[v]}], 3,
                &out.positions[3 * std::size_t{v}]);
  }
  for (std::uint32_t f = 0; f < nf; ++f) {
    std::uint32_t cf = order.face[f], r = order.rotation[f];
    for (std::uint32_t c = 0; c < 4; ++c)
      out.quads[4 * f + (c + r) % 4] = canonical_to_input[canonical.quads[4 * cf + c]];
  }
  return out;
}

FileTopology file_topology(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p = parse_container(bytes, limits);
  decode_components(p);
  return {std::move(p.codes), p.counts.unreferenced};
}

OrderMap file_order(std::string_view bytes, const DecodeLimits& limits) {
  const Parsed p = parse_container(bytes, limits);
  if (!p.order) return {};
  return decode_order(p.order->payload, p.order->payload_offset,
                      static_cast<std::uint32_t>(p.counts.vertices),
                      static_cast<std::uint32_t>(p.counts.faces), stream_ends(p));
}

FileInfo inspect(std::string_view bytes, const DecodeLimits& limits) {
  Parsed p = parse_container(bytes, limits);
  decode_components(p);
  FileInfo info;
  info.version_major = p.major;
  info.version_minor = p.minor;
  info.total_bytes = bytes.size();
  info.vertices = p.counts.vertices;
  info.faces = p.counts.faces;
  info.unreferenced = p.counts.unreferenced;
  info.keep_order = p.order.has_value();
  if (!p.geometry->payload.empty())
    info.geometry_revision = static_cast<std::uint8_t>(p.geometry->payload[0]);
  info.geometry_order = coding_order_of(p);
  std::uint64_t in_sections = 0;
  for (const Section& s : p.sections) {
    std::uint64_t size = s.payload_offset + s.payload.size() - s.offset;
    in_sections += size;
    info.sections.push_back({s.tag, s.offset, size});
    if (s.tag == kTagCounts || s.tag == kTagTopology)
      info.connectivity_bytes += size;
    else if (s.tag == kTagGeometry)
      info.geometry_bytes += size;
    else if (s.tag == kTagOrder)
      info.order_bytes += size;
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
  std::vector<std::uint32_t> quads;
  std::vector<GridLayout::Stencil> stencil;
  assemble(p.parts, static_cast<std::uint32_t>(p.counts.unreferenced), CodingOrder::kLayout, quads, stencil);
  const Adjacency adj =
      rebuilt_adjacency(quads, static_cast<std::uint32_t>(stencil.size()), p.topology->payload_offset);
  info.edges = adj.halfedge_count() / 2;
  info.extraordinary = extraordinary_vertices(adj).size();
  return info;
}

}  // namespace qsp
