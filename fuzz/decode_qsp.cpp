// libFuzzer target: the .qsp decoder (decode, decode_polygons with texture coordinates, inspect and
// file_comments) on hostile bytes.
// Each input is tried as is (magic, version, size and checksum checks) and, when it is shaped like a
// container, re-sealed with a correct size and checksum so mutations reach the section parsers.
// Properties: no crash, no sanitizer report, no internal error, memory bounded by the limits below;
// a file that decodes gives a valid manifold quad mesh that inspect() agrees with and that
// round-trips through encode/decode.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_check.h"
#include "qsp_craft.h"

namespace {

// Small limits keep every accepted declaration cheap; the decoder must refuse beyond them before
// allocating (hardening.sh runs this with -malloc_limit_mb far below what 2^26 faces would need).
qsp::DecodeLimits fuzz_limits() {
  qsp::DecodeLimits l;
  l.max_vertices = 1u << 18;
  l.max_faces = 1u << 18;
  return l;
}

// decode_polygons on the same bytes (any 3.x file, the 3.1 polygons section included): a file it
// accepts gives faces of degree >= 3 on its vertices, none repeating a vertex, within the limits.
void check_polygons(std::string_view bytes, const qsp::DecodeLimits& limits) {
  using namespace qsp;
  PolygonMesh m;
  try {
    m = decode_polygons(bytes, limits);
  } catch (const Error& e) {
    fuzz::check_error(e, "decode_polygons");
    return;
  }
  if (m.vertex_count() > limits.max_vertices || m.face_count() > limits.max_faces)
    fuzz::finding("decoded polygon mesh exceeds the limits");
  if (m.face_offsets.empty() || m.face_offsets.back() != m.corners.size())
    fuzz::finding("decoded polygon mesh has inconsistent face offsets");
  // Texture coordinates (3.2): every corner names one of them or none; every value is finite.
  if (m.texcoord_components > 3 || (m.texcoord_components == 0) != m.corner_texcoords.empty() ||
      (m.texcoord_components &&
       (m.texcoords.size() % m.texcoord_components != 0 || m.corner_texcoords.size() != m.corners.size())))
    fuzz::finding("decoded texture coordinate arrays disagree");
  for (const std::uint32_t t : m.corner_texcoords)
    if (t != kInvalid && std::size_t{t} * m.texcoord_components >= m.texcoords.size())
      fuzz::finding("decoded a corner naming a texture coordinate out of range");
  for (const float x : m.texcoords)
    if (!std::isfinite(x)) fuzz::finding("decoded a texture coordinate that is not finite");
  // Face labels (3.3): one per face or none, in range, names distinct and without line breaks (a name
  // is written as a statement's text).
  for (const FaceLabels* l : {&m.objects, &m.groups, &m.materials, &m.smoothing}) {
    if (!l->face.empty() && l->face.size() != m.face_count())
      fuzz::finding("decoded labels of another face count");
    for (const std::uint32_t n : l->face)
      if (n != kInvalid && n >= l->names.size()) fuzz::finding("decoded a face label out of range");
    std::vector<std::string> names = l->names;
    std::sort(names.begin(), names.end());
    if (std::adjacent_find(names.begin(), names.end()) != names.end()) fuzz::finding("decoded a name twice");
    for (const std::string& n : l->names)
      if (n.find_first_of("\r\n") != std::string::npos) fuzz::finding("a label name holds a line break");
  }
  // Normals (3.5): every corner names one of them or none; every value is finite.
  if (m.normals.size() % 3 != 0 || (!m.corner_normals.empty() && m.corner_normals.size() != m.corners.size()))
    fuzz::finding("decoded normal arrays disagree");
  for (const std::uint32_t n : m.corner_normals)
    if (n != kInvalid && std::size_t{n} * 3 >= m.normals.size())
      fuzz::finding("decoded a normal out of range");
  for (const float x : m.normals)
    if (!std::isfinite(x)) fuzz::finding("decoded a normal that is not finite");
  // Exact positions (3.6): none, or each coordinate's finite float64, which rounds to its float32.
  if (!m.positions64.empty() && m.positions64.size() != m.positions.size())
    fuzz::finding("decoded exact positions of another vertex count");
  for (std::size_t i = 0; i < m.positions64.size(); ++i)
    if (!std::isfinite(m.positions64[i]) ||
        std::bit_cast<std::uint32_t>(static_cast<float>(m.positions64[i])) !=
            std::bit_cast<std::uint32_t>(m.positions[i]))
      fuzz::finding("decoded an exact position that does not round to its float32 position");
  // Colours (3.8): 3 or 4 finite values per vertex, 1, 3 or 4 per face, or none.
  const unsigned kv = m.vertex_color_components, kf = m.face_color_components;
  if ((kv != 0 && kv != 3 && kv != 4) || (kf != 0 && kf != 1 && kf != 3 && kf != 4) ||
      m.vertex_colors.size() != kv * m.vertex_count() || m.face_colors.size() != kf * m.face_count())
    fuzz::finding("decoded colour arrays disagree with the mesh");
  for (const std::vector<float>* colors : {&m.vertex_colors, &m.face_colors})
    for (const float x : *colors)
      if (!std::isfinite(x)) fuzz::finding("decoded a colour that is not finite");
  // Subdivision tags (3.4): crease, corner and hole name vertices and faces of the output.
  for (const SubdivisionTag& t : m.tags) {
    const bool faces = t.name == "hole";
    if (t.name != "crease" && t.name != "corner" && !faces) continue;
    for (const std::int64_t i : t.ints)
      if (i < 0 || static_cast<std::uint64_t>(i) >= (faces ? m.face_count() : m.vertex_count()))
        fuzz::finding("decoded a tag index out of range");
  }
  // Properties (3.14): one value, or one list, per vertex or face; names a PLY header can hold.
  for (const auto* props : {&m.vertex_properties, &m.face_properties}) {
    const std::size_t n = props == &m.vertex_properties ? m.vertex_count() : m.face_count();
    for (const ValueProperty& p : *props) {
      if (p.list ? p.offsets.size() != n + 1 || p.offsets.back() != p.values.size() : p.values.size() != n)
        fuzz::finding("decoded a property of another element count");
      for (const char c : p.name)
        if (c <= ' ' || c > '~') fuzz::finding("decoded a property name a PLY header cannot hold");
    }
  }
  for (const std::string& n : m.material_libraries)
    if (n.find_first_of("\r\n") != std::string::npos) fuzz::finding("a material library holds a line break");
  std::vector<std::uint32_t> seen(m.vertex_count(), ~0u);
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    if (m.face_offsets[f + 1] < m.face_offsets[f] + 3)
      fuzz::finding("decoded a face of fewer than 3 corners");
    for (std::uint32_t c = m.face_offsets[f]; c < m.face_offsets[f + 1]; ++c) {
      const std::uint32_t v = m.corners[c];
      if (v >= m.vertex_count()) fuzz::finding("decoded a corner out of range");
      if (seen[v] == f) fuzz::finding("decoded a face repeating a vertex");
      seen[v] = static_cast<std::uint32_t>(f);
    }
  }
}

void check(std::string_view bytes) {
  using namespace qsp;
  const DecodeLimits limits = fuzz_limits();
  check_polygons(bytes, limits);
  QuadMesh mesh;
  bool decoded = false;
  try {
    mesh = decode(bytes, limits);
    decoded = true;
  } catch (const Error& e) {
    fuzz::check_error(e, "decode");
  }
  try {  // the comments section: no line break ever comes out (it would become a statement)
    for (const std::string& line : file_comments(bytes))
      if (line.find_first_of("\r\n") != std::string::npos) fuzz::finding("a comment line holds a line break");
  } catch (const Error& e) {
    fuzz::check_error(e, "file_comments");
  }
  FileInfo info;
  bool inspected = false;
  try {
    info = inspect(bytes, limits);
    inspected = true;
  } catch (const Error& e) {
    fuzz::check_error(e, "inspect");
  }
  if (!decoded) return;
  if (!inspected) fuzz::finding("decode accepted a file that inspect refuses");
  if (info.vertices != mesh.vertex_count() || info.faces != mesh.face_count()) {
    fuzz::finding("inspect counts differ from the decoded mesh");
  }
  if (mesh.vertex_count() > limits.max_vertices || mesh.face_count() > limits.max_faces) {
    fuzz::finding("decoded mesh exceeds the limits");
  }
  try {
    Adjacency adj = build_adjacency(mesh);
    (void)adj;
  } catch (const Error& e) {
    fuzz::finding(std::string("decoder returned an invalid mesh: ") + e.what());
  }
  if (!fuzz::check_round_trip(mesh, "decoded mesh")) fuzz::finding("decoded mesh is refused by encode");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  check(in);
  const std::string sealed = qsp::craft::reseal(in);
  if (!sealed.empty() && sealed != in) check(sealed);
  return 0;
}
