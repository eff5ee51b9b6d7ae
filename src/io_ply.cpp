// PLY through OpenMesh. OpenMesh "repairs" input silently (duplicates vertices at non-manifold
// spots, drops or splits faces) and still reports success, so qsp parses the header itself and
// refuses any result whose counts or face sizes differ from what the file declares.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <charconv>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp {
namespace {

struct PlyProperty {
  std::string name;
  int size = 0;        // bytes of one value (the count's size for a list)
  bool list = false;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t header_line = 0;
  std::vector<PlyProperty> properties;

  bool has(std::string_view n) const {
    for (const auto& p : properties) {
      if (p.name == n) return true;
    }
    return false;
  }
};

struct PlyHeader {
  bool ascii = false;
  std::size_t data_offset = 0;  // first byte after end_header's newline
  std::vector<PlyElement> elements;
};

int type_size(std::string_view t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t s = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > s) words.push_back(line.substr(s, i - s));
  }
  return words;
}

[[noreturn]] void fail_at(ErrorCode code, const std::string& path, std::uint64_t line, const std::string& what) {
  throw Error(code, path + ":" + std::to_string(line) + ": " + what);
}

PlyHeader parse_header(std::string_view bytes, const std::string& path) {
  PlyHeader h;
  std::size_t pos = 0;
  std::uint64_t line_no = 0;
  bool have_format = false;
  constexpr std::size_t kMaxHeader = 1 << 20;
  for (;;) {
    const std::size_t nl = bytes.find('\n', pos);
    if (nl == std::string_view::npos || nl > kMaxHeader) {
      fail_at(ErrorCode::kParse, path, line_no + 1, "PLY header has no end_header line");
    }
    std::string_view line = bytes.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const auto w = split_words(line);
    if (line_no == 1) {
      if (w.size() != 1 || w[0] != "ply") fail_at(ErrorCode::kParse, path, 1, "not a PLY file (no 'ply' magic line)");
      continue;
    }
    if (w.empty()) continue;
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3 || w[2] != "1.0") fail_at(ErrorCode::kParse, path, line_no, "malformed PLY format line");
      if (w[1] == "ascii") {
        h.ascii = true;
      } else if (w[1] != "binary_little_endian" && w[1] != "binary_big_endian") {
        fail_at(ErrorCode::kParse, path, line_no, "unknown PLY format '" + std::string(w[1].substr(0, 40)) + "'");
      }
      have_format = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) fail_at(ErrorCode::kParse, path, line_no, "malformed PLY element line");
      PlyElement e;
      e.name = std::string(w[1]);
      e.header_line = line_no;
      const auto r = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
      if (r.ec != std::errc() || r.ptr != w[2].data() + w[2].size()) {
        fail_at(ErrorCode::kParse, path, line_no, "malformed PLY element count '" + std::string(w[2].substr(0, 40)) + "'");
      }
      h.elements.push_back(std::move(e));
    } else if (w[0] == "property") {
      if (h.elements.empty()) fail_at(ErrorCode::kParse, path, line_no, "PLY property before any element");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        p.list = true;
        p.size = type_size(w[2]);
        if (type_size(w[3]) == 0) p.size = 0;
        p.name = std::string(w[4]);
      } else if (w.size() == 3) {
        p.size = type_size(w[1]);
        p.name = std::string(w[2]);
      }
      if (p.size == 0) fail_at(ErrorCode::kParse, path, line_no, "malformed PLY property line");
      h.elements.back().properties.push_back(std::move(p));
    } else if (w[0] == "end_header") {
      break;
    } else {
      fail_at(ErrorCode::kParse, path, line_no, "unknown PLY header line '" + std::string(w[0].substr(0, 40)) + "'");
    }
  }
  if (!have_format) fail_at(ErrorCode::kParse, path, 2, "PLY header has no format line");
  h.data_offset = pos;
  return h;
}

bool is_color(std::string_view n) {
  return n == "red" || n == "green" || n == "blue" || n == "alpha" || n == "r" || n == "g" || n == "b" ||
         n == "a" || n.substr(0, 8) == "diffuse_";
}
bool is_texcoord(std::string_view n) {
  return n == "u" || n == "v" || n == "s" || n == "t" || n.substr(0, 8) == "texture_" || n == "texcoord";
}
bool is_normal(std::string_view n) { return n == "nx" || n == "ny" || n == "nz"; }

// Counts what qsp will not store, and checks the declared counts fit the data that follows.
void check_header(const PlyHeader& h, std::string_view bytes, const std::string& path, ReadReport& r,
                  std::uint64_t* vertices, std::uint64_t* faces) {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  std::uint64_t min_bytes = 0;
  for (const auto& e : h.elements) {
    std::uint64_t per = 0;
    for (const auto& p : e.properties) per += h.ascii ? 2 : static_cast<std::uint64_t>(p.size);
    if (e.count > (std::uint64_t{1} << 40) || (per && e.count > (bytes.size() - h.data_offset) / per)) {
      fail_at(ErrorCode::kParse, path, e.header_line,
              "PLY header declares " + std::to_string(e.count) + " " + e.name + " elements but only " +
                  std::to_string(bytes.size() - h.data_offset) + " bytes of data follow (truncated file?)");
    }
    min_bytes += e.count * per;
    if (e.name == "vertex") {
      vertex = &e;
    } else if (e.name == "face") {
      face = &e;
    } else if (e.count > 0) {
      fail_at(ErrorCode::kUnsupported, path, e.header_line,
              "PLY element '" + e.name.substr(0, 40) + "' is not supported; qsp stores quad meshes only");
    }
  }
  if (min_bytes > bytes.size() - h.data_offset) {
    fail_at(ErrorCode::kParse, path, h.elements.empty() ? 1 : h.elements.back().header_line,
            "PLY header declares more data than the file holds (truncated file?)");
  }
  if (!vertex || !vertex->has("x") || !vertex->has("y") || !vertex->has("z")) {
    fail_at(ErrorCode::kParse, path, vertex ? vertex->header_line : 1, "PLY file has no vertex element with x, y, z");
  }
  if (vertex->count > kMaxVertices) {
    fail_at(ErrorCode::kLimit, path, vertex->header_line,
            std::to_string(vertex->count) + " vertices; qsp's limit is " + std::to_string(kMaxVertices));
  }
  bool normals = false, colors = false, texcoords = false, other = false;
  for (const auto& p : vertex->properties) {
    if (p.name == "x" || p.name == "y" || p.name == "z") continue;
    (is_normal(p.name) ? normals : is_color(p.name) ? colors : is_texcoord(p.name) ? texcoords : other) = true;
  }
  if (normals) r.normals += vertex->count;
  if (colors) r.vertex_colors += vertex->count;
  if (texcoords) r.texcoords += vertex->count;
  if (other) r.other_properties += vertex->count;
  *vertices = vertex->count;
  *faces = 0;
  if (!face) return;
  if (!face->has("vertex_indices") && !face->has("vertex_index")) {
    fail_at(ErrorCode::kParse, path, face->header_line, "PLY face element has no vertex_indices list");
  }
  if (face->count > kMaxFaces) {
    fail_at(ErrorCode::kLimit, path, face->header_line,
            std::to_string(face->count) + " faces; qsp's limit is " + std::to_string(kMaxFaces));
  }
  bool fcolors = false, fattr = false;
  other = false;
  for (const auto& p : face->properties) {
    if (p.name == "vertex_indices" || p.name == "vertex_index") continue;
    (is_color(p.name) ? fcolors : is_texcoord(p.name) ? fattr : other) = true;
  }
  if (fcolors) r.face_colors += face->count;
  if (fattr) r.face_attribute_refs += face->count;
  if (other) r.other_properties += face->count;
  *faces = face->count;
}

using PlyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

}  // namespace

QuadMesh read_ply_file(const std::string& path, ReadReport* report) {
  ReadReport local;
  ReadReport& r = report ? *report : local;
  r = ReadReport{};
  const std::string bytes = read_file_bytes(path);
  const PlyHeader header = parse_header(bytes, path);
  std::uint64_t vertices = 0, faces = 0;
  check_header(header, bytes, path, r, &vertices, &faces);

  PlyMesh om;
  OpenMesh::IO::Options options;  // positions only: qsp keeps nothing else
  std::istringstream stream(bytes, std::ios::in | std::ios::binary);
  // OpenMesh reports its repairs on stderr; qsp's own message below says what matters.
  ::omerr().disable();
  const bool ok = OpenMesh::IO::read_mesh(om, stream, ".ply", options);
  ::omerr().enable();
  if (!ok) throw Error(ErrorCode::kParse, path + ": OpenMesh could not read this PLY file (malformed data?)");

  if (om.n_vertices() != vertices) {
    throw Error(ErrorCode::kNonManifold,
                path + ": the header declares " + std::to_string(vertices) + " vertices but OpenMesh produced " +
                    std::to_string(om.n_vertices()) +
                    " (it duplicates vertices where faces meet non-manifoldly); refusing a rewritten mesh");
  }
  if (om.n_faces() != faces) {
    throw Error(ErrorCode::kNonManifold,
                path + ": the header declares " + std::to_string(faces) + " faces but OpenMesh kept " +
                    std::to_string(om.n_faces()) +
                    " (it drops non-manifold or degenerate faces, e.g. ones repeating a vertex); refusing a "
                    "rewritten mesh");
  }
  QuadMesh mesh;
  mesh.positions.reserve(3 * vertices);
  for (const auto vh : om.vertices()) {
    const auto& p = om.point(vh);
    mesh.positions.insert(mesh.positions.end(), {p[0], p[1], p[2]});
  }
  std::uint64_t non_quads = 0;
  std::string examples;
  mesh.quads.reserve(4 * faces);
  for (const auto fh : om.faces()) {
    // OpenMesh's add_face keeps the corner order and gives the face the halfedge from the last
    // corner to the first, so walking to_vertex from it yields the file's corners from the first
    // (tests/test_io.cpp checks this against the file).
    const auto h0 = om.halfedge_handle(fh);
    std::uint32_t q[4];
    std::size_t n = 0;
    auto h = h0;
    do {
      if (n < 4) q[n] = static_cast<std::uint32_t>(om.to_vertex_handle(h).idx());
      ++n;
      h = om.next_halfedge_handle(h);
    } while (h != h0 && n <= 1024);
    if (n != 4) {
      if (non_quads < 3) {
        if (!examples.empty()) examples += ", ";
        examples += "face " + std::to_string(fh.idx()) + ": " +
                    (n == 3 ? std::string("triangle") : std::to_string(n) + " vertices");
      }
      ++non_quads;
      continue;
    }
    mesh.quads.insert(mesh.quads.end(), q, q + 4);
  }
  if (non_quads) {
    throw Error(ErrorCode::kNotQuad, path + ": " + std::to_string(non_quads) +
                                         (non_quads == 1 ? " face is not a quad (" : " faces are not quads (first: ") +
                                         examples + (non_quads > 3 ? ", ..." : "") +
                                         "); qsp stores quad meshes only and never triangulates or drops faces");
  }
  r.face_line.assign(faces, 0);  // binary or not, PLY faces have no reliable line
  return mesh;
}

}  // namespace qsp
