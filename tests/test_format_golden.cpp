// Pins the .qsp bytes (testdata/golden: the natural files of the highest level, polygon meshes (format
// 3.1's polygons section) and "_comments" files (its comments section) among them, and in
// testdata/golden/tools/ one file per combination of the geometry tools), the refusal of every damaged
// or crafted file (testdata/invalid/*.qsp + .expect), and the spec's own worked example.
// QSP_UPDATE_GOLDEN=1 rewrites the golden .qsp files and the crafted invalid files: only for a
// deliberate format change, which also needs a new version and a changes-log entry in the spec, and
// never for the files of a released version (testdata/golden/vX.Y/, see CONTRIBUTING.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "bytes.h"
#include "codec_encode.h"
#include "codec_sections.h"
#include "container.h"
#include "mirror.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/geometry.h"
#include "qsp/io.h"
#include "qsp/polymesh.h"
#include "qsp/submesh.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/minor.h"
#include "support/polygon.h"
#include "support/quantized.h"

namespace fs = std::filesystem;

namespace qsp {
namespace {

const std::string kGolden = std::string(QSP_TESTDATA_DIR) + "/golden";
const std::string kTools = kGolden + "/tools";
const std::string kInvalid = std::string(QSP_TESTDATA_DIR) + "/invalid";
// Only QSP_UPDATE_GOLDEN=1 rewrites: any other value (0 included) checks, as an unset variable does.
bool updating() {
  const char* v = std::getenv("QSP_UPDATE_GOLDEN");
  return v && std::string(v) == "1";
}

using testing::slurp;
using testing::spit;

// The goldens' names: testdata/golden/NAME.obj, polygons/NAME.obj for polygon meshes,
// texcoords/NAME.obj for meshes with texture coordinates and labels/NAME.obj for meshes with face
// labels (kept out of testdata/golden itself, whose
// meshes the test corpus reads as valid quad meshes without other data).
std::vector<std::string> golden_names() {
  std::vector<std::string> out;
  for (const char* dir : {"", "polygons/", "texcoords/", "labels/", "tags/", "normals/", "exact/", "kept/",
                          "colors/", "statements/", "mirror/"}) {
    for (const auto& e : fs::directory_iterator(kGolden + "/" + dir)) {
      if (e.path().extension() == ".obj") out.push_back(std::string(dir) + e.path().stem().string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

EncodeOptions options_for(const std::string& name) {
  EncodeOptions o;
  // The search is the level's, not the format's: these pin the files of the one that tries the most.
  o.level = kMaxLevel;
  o.keep_order = name.find("_keep_order") != std::string::npos;
  // The partition is an encoder choice, not the format: these pin the motorcycle graph's files (and
  // one greedy partition's), whichever the encoder would pick.
  o.partition =
      name.find("_greedy") != std::string::npos ? PartitionMode::kGreedy : PartitionMode::kMotorcycle;
  // "_q14": positions quantized to 14 bits (the other goldens are lossless).
  if (name.find("_q14") != std::string::npos) o.quantize_bits = 14;
  // "_uv12": texture coordinates on the binary grid of step 2^-12.
  if (name.find("_uv12") != std::string::npos) o.quantize_texcoord_bits = 12;
  // "_c8": colours on the binary grid of step 2^-8.
  if (name.find("_c8") != std::string::npos) o.quantize_color_bits = 8;
  // "_qn10": octahedral normals of 10 bits.
  if (name.find("_qn10") != std::string::npos) o.quantize_normal_bits = 10;
  // The encoder picks patch order for every other golden; this pins the layout-order bytes.
  if (name.find("_layout_order") != std::string::npos) o.geometry_order = CodingOrder::kLayout;
  return o;
}

// `decoded` is `mesh` renumbered, read without the encoder's order map: each vertex of `mesh` has its
// own decoded vertex within `bound` on every axis (bit for bit when 0), and the faces are the same
// quads of those vertices, each up to its first corner.
void expect_same_mesh(const QuadMesh& mesh, const QuadMesh& decoded, double bound) {
  ASSERT_EQ(decoded.vertex_count(), mesh.vertex_count());
  ASSERT_EQ(decoded.face_count(), mesh.face_count());
  const std::size_t n = mesh.vertex_count();
  std::vector<std::uint32_t> to(n);
  std::vector<bool> taken(n);
  for (std::size_t v = 0; v < n; ++v) {
    double best = INFINITY;
    for (std::size_t u = 0; u < n; ++u) {
      double d = 0;
      for (int k = 0; k < 3; ++k)
        d = std::max(d, std::abs(double{decoded.positions[3 * u + k]} - double{mesh.positions[3 * v + k]}));
      if (d < best) best = d, to[v] = static_cast<std::uint32_t>(u);
    }
    ASSERT_LE(best, bound) << "vertex " << v << " has no decoded vertex near enough";
    ASSERT_FALSE(taken[to[v]]) << "vertex " << v << ": its nearest decoded vertex is another's";
    taken[to[v]] = true;
    if (bound == 0) {
      ASSERT_EQ(std::memcmp(&decoded.positions[3 * to[v]], &mesh.positions[3 * v], 12), 0) << "vertex " << v;
    }
  }
  // Each face as its corners from the smallest, so the canonical file's choice of first corner is free.
  const auto faces = [](const std::vector<std::uint32_t>& q, const std::vector<std::uint32_t>* map) {
    std::vector<std::array<std::uint32_t, 4>> out;
    for (std::size_t f = 0; f < q.size() / 4; ++f) {
      std::array<std::uint32_t, 4> c;
      for (int k = 0; k < 4; ++k) c[k] = map ? (*map)[q[4 * f + k]] : q[4 * f + k];
      std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
      out.push_back(c);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(faces(mesh.quads, &to), faces(decoded.quads, nullptr));
}

// The geometry tools a golden of testdata/golden/tools/ pins, from the letters after the mesh's name:
// r value repeats, l layout order, c normal chaining, s cell shapes, m logistic mixing ("plain": none).
struct ToolGolden {
  std::string name;  // file name without .qsp
  std::string mesh;  // testdata/golden/MESH.obj
  std::uint8_t tools;
};

// Every combination of the five tools, on one quantized mesh (every tool has something to do there:
// three integer axes, full cells, repeated values) and, for the value domains, a few on a lossless one.
std::vector<ToolGolden> tool_goldens() {
  std::vector<ToolGolden> out;
  auto letters = [](std::uint8_t tools) {
    std::string s;
    const char* names = "rlcsmy";
    for (int b = 0; b < 6; ++b)
      if (tools & (1 << b)) s += names[b];
    return s.empty() ? std::string("plain") : s;
  };
  for (std::uint8_t tools = 0; tools <= 0x1F; ++tools)  // the tools of 3.0 (3.17's mirror: below)
    out.push_back({"tilted_noise_q14_" + letters(tools), "tilted_noise_q14", tools});
  for (std::uint8_t tools : {0x00, 0x01, 0x06, 0x19, 0x1F})
    out.push_back({"tilted_noise_" + letters(tools), "tilted_noise", tools});
  // Mirror prediction (3.17) with every combination of the others, on a mesh that has a mirror.
  for (std::uint8_t tools = 0x20; tools <= 0x3F; ++tools)
    out.push_back({"hull_q14_" + letters(tools), "mirror/hull_q14", tools});
  out.push_back({"hull_" + letters(0x3D), "mirror/hull", 0x3D});
  return out;
}

std::string encode_tool_golden(const ToolGolden& g) {
  EncodeOptions o = options_for(g.mesh);
  o.geometry_order = (g.tools & geometry_tool::kLayoutOrder) ? CodingOrder::kLayout : CodingOrder::kPatch;
  return encode_tuned(read_mesh_file(kGolden + "/" + g.mesh + ".obj"), o, {g.tools});
}

// Every pinned file: the natural goldens and the tool combinations.
std::vector<std::string> golden_paths() {
  std::vector<std::string> paths;
  for (const auto& name : golden_names()) paths.push_back(kGolden + "/" + name + ".qsp");
  for (const ToolGolden& g : tool_goldens()) paths.push_back(kTools + "/" + g.name + ".qsp");
  return paths;
}

// A golden's .obj as any polygon mesh (float32 positions, faces as read, texture coordinates).
// The goldens under statements/ keep the file's statement order (the others pin the bytes without it).
PolygonMesh read_polygons(const std::string& path) {
  if (path.find("/statements/") == std::string::npos) return testing::read_obj_polygons(path);
  return to_polygon_mesh(read_obj_mesh(testing::slurp(path), path), kPolygonMeshCategories | kCategoryExtra);
}

// The corners of a decoded all-quad PolygonMesh, as a QuadMesh's quads.
std::vector<std::uint32_t> polygon_faces_as_quads(const PolygonMesh& m) { return m.corners; }

bool is_quad_mesh(const PolygonMesh& m) {
  for (std::size_t f = 0; f < m.face_count(); ++f)
    if (m.degree(f) != 4) return false;
  return true;
}

// What `qsp compress` writes for a golden: its mesh at the golden's options, and for a "_comments"
// golden the .obj's leading comment block in the comments section (the other goldens' descriptive
// headers are left out, as `--drop comment` leaves them out).
std::string encode_golden(const std::string& name) {
  const std::string path = kGolden + "/" + name + ".obj";
  const PolygonMesh poly = read_polygons(path);
  std::string bytes = is_quad_mesh(poly) && !poly.texcoord_components && !poly.has_labels() &&
                              poly.tags.empty() && poly.corner_normals.empty() && poly.positions64.empty() &&
                              poly.kept_lines.empty() && !poly.vertex_color_components &&
                              !poly.face_color_components
                          ? encode(read_mesh_file(path), options_for(name))
                          : encode_polygons(poly, options_for(name));
  if (name.find("_comments") != std::string::npos)
    bytes = with_comments(bytes, leading_comments(slurp(path)));
  return bytes;
}

// `decoded` is the polygon mesh `mesh` renumbered (positions bit for bit): the same vertices, and the
// same faces with the same corner cycles, each up to its first corner, in any order.
void expect_same_polygons(const PolygonMesh& mesh, const PolygonMesh& decoded) {
  ASSERT_EQ(decoded.vertex_count(), mesh.vertex_count());
  ASSERT_EQ(decoded.face_count(), mesh.face_count());
  using Bits = std::array<std::uint32_t, 3>;
  const auto bits = [](const PolygonMesh& m, std::size_t v) {
    Bits b;
    std::memcpy(b.data(), &m.positions[3 * v], 12);
    return b;
  };
  std::map<Bits, std::uint32_t> at;
  for (std::size_t v = 0; v < decoded.vertex_count(); ++v)
    ASSERT_TRUE(at.emplace(bits(decoded, v), static_cast<std::uint32_t>(v)).second)
        << "two vertices at one place";
  std::vector<std::uint32_t> to(mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const auto it = at.find(bits(mesh, v));
    ASSERT_NE(it, at.end()) << "vertex " << v << " has no decoded vertex at its position";
    to[v] = it->second;
  }
  // Each corner: its vertex, then its texture coordinate's float bits (none: kInvalid); each face's
  // labels by name.
  ASSERT_EQ(decoded.texcoord_components, mesh.texcoord_components);
  EXPECT_EQ(decoded.material_libraries, mesh.material_libraries);
  const auto faces = [](const PolygonMesh& m, const std::vector<std::uint32_t>* map) {
    using Corner = std::array<std::uint32_t, 7>;
    std::vector<std::pair<std::vector<Corner>, std::string>> out;
    for (std::size_t f = 0; f < m.face_count(); ++f) {
      std::vector<Corner> c;
      for (std::uint32_t k = m.face_offsets[f]; k < m.face_offsets[f + 1]; ++k) {
        Corner x;
        x.fill(qsp::kInvalid);
        x[0] = map ? (*map)[m.corners[k]] : m.corners[k];
        const std::uint32_t t = m.corner_texcoords.empty() ? qsp::kInvalid : m.corner_texcoords[k];
        for (std::uint32_t i = 0; t != qsp::kInvalid && i < m.texcoord_components; ++i)
          std::memcpy(&x[1 + i], &m.texcoords[std::size_t{t} * m.texcoord_components + i], 4);
        const std::uint32_t n = m.corner_normals.empty() ? qsp::kInvalid : m.corner_normals[k];
        if (n != qsp::kInvalid) std::memcpy(&x[4], &m.normals[3 * std::size_t{n}], 12);
        c.push_back(x);
      }
      std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
      std::string labels;
      for (const FaceLabels* l : {&m.objects, &m.groups, &m.materials, &m.smoothing})
        labels +=
            (l->face.empty() || l->face[f] == qsp::kInvalid ? "-" : "'" + l->names[l->face[f]] + "'") + "|";
      out.emplace_back(c, labels);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(faces(mesh, &to), faces(decoded, nullptr));
}

TEST(Golden, BytesArePinned) {
  auto names = golden_names();
  ASSERT_GE(names.size(), 5u);
  int polygons = 0, comments = 0, coded_comments = 0, texcoords = 0, labels = 0, tags = 0, normals = 0,
      exact = 0, kept = 0, colors = 0, statements = 0, exact_values = 0;
  for (const auto& name : names) {
    SCOPED_TRACE(name);
    const std::string obj = kGolden + "/" + name + ".obj";
    std::string bytes = encode_golden(name);
    std::string path = kGolden + "/" + name + ".qsp";
    if (updating()) spit(path, bytes);
    ASSERT_TRUE(fs::exists(path));
    EXPECT_EQ(bytes, slurp(path)) << "the encoder's output changed: a format change needs a version bump";
    const std::vector<std::string> lines = file_comments(slurp(path));
    EXPECT_EQ(lines, name.find("_comments") != std::string::npos ? leading_comments(slurp(obj))
                                                                 : std::vector<std::string>{});
    comments += !lines.empty();
    coded_comments += container::parse(slurp(path)).find(container::kTagCodedComments) != nullptr;
    PolygonMesh poly = read_polygons(obj);
    if (!poly.texcoords64.empty() || !poly.normals64.empty() || !poly.vertex_colors64.empty()) {
      // Exact values: a 3.13 file, decoded to the .obj's faces with each texture coordinate, normal and
      // vertex colour's binary64 value (found by its binary32s), array for array with the order kept.
      ++exact_values;
      EXPECT_EQ(slurp(path)[9], testing::minor_of_file_with(slurp(path), 13))
          << "a file with exact values says format 3.13";
      const PolygonMesh back = decode_polygons(slurp(path));
      expect_same_polygons(poly, back);
      const auto pairs = [](const std::vector<float>& f, const std::vector<double>& d) {
        std::multiset<std::pair<std::uint32_t, std::uint64_t>> out;
        for (std::size_t i = 0; i < d.size(); ++i)
          out.emplace(std::bit_cast<std::uint32_t>(f[i]), std::bit_cast<std::uint64_t>(d[i]));
        return out;
      };
      for (const auto& [f, d, bf, bd] :
           {std::tuple{&poly.texcoords, &poly.texcoords64, &back.texcoords, &back.texcoords64},
            std::tuple{&poly.normals, &poly.normals64, &back.normals, &back.normals64},
            std::tuple{&poly.vertex_colors, &poly.vertex_colors64, &back.vertex_colors,
                       &back.vertex_colors64}}) {
        ASSERT_EQ(bd->size(), d->size());
        EXPECT_EQ(pairs(*bf, *bd), pairs(*f, *d));
        if (options_for(name).keep_order && !d->empty()) {
          EXPECT_EQ(std::memcmp(bd->data(), d->data(), 8 * d->size()), 0);
        }
      }
      continue;
    }
    if (!poly.statements.empty()) {
      // The statement order: a 3.11 file, whose decoded mesh written as OBJ has the .obj's statements in
      // its order (its non-comment lines, the numbers as they were written: integers and short decimals).
      ++statements;
      EXPECT_EQ(slurp(path)[9], testing::minor_of_file_with(slurp(path), 11))
          << "a file with the statement order says format 3.11";
      const PolygonMesh back = decode_polygons(slurp(path));
      ASSERT_EQ(back.statements.size(), poly.statements.size());
      const std::string text = write_obj_mesh(from_polygon_mesh(back));
      std::string want;
      std::istringstream in(slurp(obj));
      for (std::string line; std::getline(in, line);)
        if (!line.starts_with("#")) want += line + "\n";
      EXPECT_EQ(text, want);
      continue;
    }
    if (poly.vertex_color_components) {
      // Colours: a 3.8 file, decoded to the .obj's faces with each vertex's colour (found by its
      // position), exactly or on the grid of step 2^-8 ("_c8"); index for index with the order kept.
      ++colors;
      EXPECT_EQ(slurp(path)[9], testing::minor_of_file_with(slurp(path), 8))
          << "a file with colours says format 3.8";
      const PolygonMesh back = decode_polygons(slurp(path));
      expect_same_polygons(poly, back);
      if (options_for(name).quantize_color_bits)
        for (float& x : poly.vertex_colors) x = std::ldexp(std::nearbyint(std::ldexp(x, 8)), -8) + 0.0f;
      std::map<std::array<float, 3>, std::vector<std::uint32_t>> color_at;
      const auto color = [](const PolygonMesh& m, std::size_t v) {
        std::vector<std::uint32_t> bits(m.vertex_color_components);
        std::memcpy(bits.data(), &m.vertex_colors[bits.size() * v], 4 * bits.size());
        return std::pair{
            std::array<float, 3>{m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]}, bits};
      };
      for (std::size_t v = 0; v < back.vertex_count(); ++v) color_at.insert(color(back, v));
      for (std::size_t v = 0; v < poly.vertex_count(); ++v)
        EXPECT_EQ(color_at[color(poly, v).first], color(poly, v).second) << "vertex " << v;
      if (options_for(name).keep_order) {
        EXPECT_EQ(back.corners, poly.corners);
        EXPECT_EQ(
            std::memcmp(back.vertex_colors.data(), poly.vertex_colors.data(), 4 * poly.vertex_colors.size()),
            0);
      }
      continue;
    }
    if (!poly.kept_lines.empty()) {
      // Kept lines: a 3.7 file (the section is optional), decoded to the .obj's faces and its lines kept
      // as text, in order; decode() skips them.
      ++kept;
      EXPECT_EQ(slurp(path)[9], testing::minor_of_file_with(slurp(path), 7))
          << "a file with kept lines says format 3.7";
      const PolygonMesh back = decode_polygons(slurp(path));
      expect_same_polygons(poly, back);
      EXPECT_EQ(back.kept_lines, poly.kept_lines);
      EXPECT_EQ(decode(slurp(path)).quads, polygon_faces_as_quads(back));
      continue;
    }
    if (!poly.positions64.empty()) {
      // Exact positions: a 3.6 file, decoded to the .obj's faces with each coordinate's binary64 value
      // (found by its binary32 position), index for index with the order kept.
      ++exact;
      EXPECT_EQ(slurp(path)[9], testing::minor_of_file_with(slurp(path), 6))
          << "a file with exact positions says format 3.6";
      const PolygonMesh back = decode_polygons(slurp(path));
      expect_same_polygons(poly, back);
      ASSERT_EQ(back.positions64.size(), back.positions.size());
      std::map<std::array<std::uint32_t, 3>, std::array<std::uint64_t, 3>> exact_at;
      const auto bits = [](const PolygonMesh& m, std::size_t v) {
        std::array<std::uint32_t, 3> f;
        std::array<std::uint64_t, 3> d;
        std::memcpy(f.data(), &m.positions[3 * v], 12);
        std::memcpy(d.data(), &m.positions64[3 * v], 24);
        return std::pair{f, d};
      };
      for (std::size_t v = 0; v < back.vertex_count(); ++v) exact_at.insert(bits(back, v));
      for (std::size_t v = 0; v < poly.vertex_count(); ++v)
        EXPECT_EQ(exact_at[bits(poly, v).first], bits(poly, v).second) << "vertex " << v;
      if (options_for(name).keep_order) {
        EXPECT_EQ(back.corners, poly.corners);
        EXPECT_EQ(std::memcmp(back.positions64.data(), poly.positions64.data(), 8 * poly.positions64.size()),
                  0);
      }
      continue;
    }
    if (!poly.corner_normals.empty()) {
      // Normals: a 3.5 file, or 3.10 with normals predicted from the faces or octahedral, decoded to the
      // .obj's corners with their normals (and texture coordinates) bit for bit (octahedral ones: within
      // the spec's 1.5 / h radians, as the same file with the order kept gives them); index for index
      // with the order kept.
      ++normals;
      const char minor = slurp(path)[9];
      EXPECT_TRUE(minor == testing::minor_of_file_with(slurp(path), 5) ||
                  minor == testing::minor_of_file_with(slurp(path), 10))
          << "a file with normals says format 3.5 or 3.10";
      const PolygonMesh back = decode_polygons(slurp(path));
      if (const std::uint32_t bits = options_for(name).quantize_normal_bits) {
        EXPECT_EQ(minor, testing::minor_of_file_with(slurp(path), 10));
        EncodeOptions in_order = options_for(name);
        in_order.keep_order = true;
        const PolygonMesh rounded = decode_polygons(encode_polygons(poly, in_order));
        ASSERT_EQ(rounded.normals.size(), poly.normals.size());
        const double h = double((1u << (bits - 1)) - 1);
        for (std::size_t i = 0; i < poly.normals.size(); i += 3) {
          const float *x = &poly.normals[i], *y = &rounded.normals[i];
          const double sine = std::hypot(double{x[1]} * y[2] - double{x[2]} * y[1],
                                         double{x[2]} * y[0] - double{x[0]} * y[2],
                                         double{x[0]} * y[1] - double{x[1]} * y[0]),
                       cosine = double{x[0]} * y[0] + double{x[1]} * y[1] + double{x[2]} * y[2];
          EXPECT_LE(std::atan2(sine, cosine), 1.5 / h + 0x1p-23) << "normal " << i / 3;
        }
        poly.normals = rounded.normals;
      }
      expect_same_polygons(poly, back);
      if (options_for(name).keep_order) {
        EXPECT_EQ(back.corner_normals, poly.corner_normals);
        EXPECT_EQ(std::memcmp(back.normals.data(), poly.normals.data(), 4 * poly.normals.size()), 0);
      }
      continue;
    }
    if (!poly.tags.empty()) {
      // Subdivision tags: a 3.4 file, decoded to the .obj's faces and its tags, their indices naming the
      // same vertices and faces (by position) in the decoder's numbering.
      ++tags;
      EXPECT_EQ(slurp(path)[9], testing::minor_of_file_with(slurp(path), 4))
          << "a file with subdivision tags says format 3.4";
      const PolygonMesh back = decode_polygons(slurp(path));
      expect_same_polygons(poly, back);
      EXPECT_EQ(testing::tags_by_position(back), testing::tags_by_position(poly));
      if (options_for(name).keep_order) {
        ASSERT_EQ(back.tags.size(), poly.tags.size());
        for (std::size_t t = 0; t < poly.tags.size(); ++t) EXPECT_EQ(back.tags[t].ints, poly.tags[t].ints);
      }
      continue;
    }
    if (poly.has_labels()) {
      // Face labels: a 3.3 file, decoded to the .obj's faces with their labels (and names, libraries).
      ++labels;
      EXPECT_EQ(slurp(path)[9],
                testing::minor_of_file_with(slurp(path), name.find("_prefixes") != std::string::npos ? 9 : 3))
          << "a file with face labels says format 3.3, 3.9 with front-coded names";
      const PolygonMesh back = decode_polygons(slurp(path));
      expect_same_polygons(poly, back);
      if (options_for(name).keep_order) {
        EXPECT_EQ(back.corners, poly.corners);
        for (auto [a, b] :
             {std::pair{&back.objects, &poly.objects}, std::pair{&back.groups, &poly.groups},
              std::pair{&back.materials, &poly.materials}, std::pair{&back.smoothing, &poly.smoothing}}) {
          ASSERT_EQ(a->face.size(), b->face.size());
          for (std::size_t f = 0; f < a->face.size(); ++f) {
            const auto name_of = [f](const FaceLabels* l) {
              return l->face[f] == qsp::kInvalid ? std::string("-") : l->names[l->face[f]];
            };
            EXPECT_EQ(name_of(a), name_of(b));
          }
        }
      }
      continue;
    }
    if (poly.texcoord_components) {
      // Texture coordinates: a 3.2 file, decoded to the .obj's corners and their texture coordinates.
      ++texcoords;
      EXPECT_EQ(slurp(path)[9], testing::minor_of_file_with(slurp(path), 2))
          << "a file with texture coordinates says format 3.2";
      const PolygonMesh back = decode_polygons(slurp(path));
      if (const std::uint32_t bits = options_for(name).quantize_texcoord_bits) {
        // Rounded as the spec says: the binary32 nearest to round(x * 2^bits) * 2^-bits.
        const int b = static_cast<int>(bits);
        for (float& x : poly.texcoords)
          x = static_cast<float>(std::ldexp(std::nearbyint(std::ldexp(static_cast<double>(x), b)), -b)) +
              0.0f;
      }
      if (options_for(name).keep_order) {
        EXPECT_EQ(back.face_offsets, poly.face_offsets);
        EXPECT_EQ(back.corners, poly.corners);
        EXPECT_EQ(back.corner_texcoords, poly.corner_texcoords);
        EXPECT_EQ(std::memcmp(back.texcoords.data(), poly.texcoords.data(), 4 * poly.texcoords.size()), 0);
      } else {
        expect_same_polygons(poly, back);
      }
      continue;
    }
    if (!is_quad_mesh(poly)) {
      // A polygon mesh: a 3.1 file with a polygons section, decoded to the .obj's faces and vertices.
      ++polygons;
      EXPECT_TRUE(inspect(slurp(path)).polygons);
      EXPECT_EQ(slurp(path)[9], testing::minor_of_file_with(slurp(path), 1))
          << "a polygon file says format 3.1";
      expect_same_polygons(poly, decode_polygons(slurp(path)));
      continue;
    }
    // The pinned file decodes to its .obj: exactly when lossless, within half a grid step when not.
    QuadMesh mesh = read_mesh_file(obj);
    QuadMesh back = decode(slurp(path));
    const std::uint32_t bits = options_for(name).quantize_bits;
    expect_same_mesh(mesh, back, bits ? testing::quantization_bound(mesh.positions, bits) : 0.0);
    if (options_for(name).keep_order) {
      EXPECT_EQ(back.quads, mesh.quads);
      if (!bits) {
        EXPECT_EQ(std::memcmp(back.positions.data(), mesh.positions.data(), 4 * mesh.positions.size()), 0);
      }
    }
  }
  // Format 3.1's two sections each have a golden.
  EXPECT_GE(polygons, 1);
  EXPECT_GE(comments, 1);
  EXPECT_GE(coded_comments, 2);  // format 3.16's coded comments section
  EXPECT_GE(texcoords, 2);
  EXPECT_GE(labels, 3);
  EXPECT_GE(tags, 3);
  EXPECT_GE(normals, 2);
  EXPECT_GE(exact, 2);
  EXPECT_GE(exact_values, 2);
  EXPECT_GE(kept, 1);
  EXPECT_GE(statements, 1);
  EXPECT_GE(colors, 3);
}

// One golden per combination of the geometry tools, each decoding to the mesh its natural golden gives
// (format-spec/geometry_section.md: every combination is valid, and a decoder reads all of them), with
// the tools and the level it says. The natural goldens use both coding orders, and the costly tools
// where they are smaller.
// Files written before 3.12 (testdata/golden/v3.11/: the polygon goldens whose interior positions the
// polygons section coded along a chain, before the geometry section coded them from their neighbours)
// decode forever, to what today's files of the same meshes decode to.
TEST(Golden, PolygonFilesBefore312StillDecode) {
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(kGolden + "/v3.11")) {
    if (e.path().extension() != ".qsp") continue;
    const std::string name = e.path().parent_path().filename().string() + "/" + e.path().stem().string();
    SCOPED_TRACE(name);
    ++files;
    const std::string old = slurp(e.path().string()), now = slurp(kGolden + "/" + name + ".qsp");
    EXPECT_LT(old[9], kFormatMinorInterior);
    EXPECT_EQ(container::parse(old).find(container::kTagInterior), nullptr);
    EXPECT_NE(container::parse(now).find(container::kTagInterior), nullptr)
        << "the golden has vertices in no quad";
    EXPECT_EQ(write_obj_mesh(from_polygon_mesh(decode_polygons(old))),
              write_obj_mesh(from_polygon_mesh(decode_polygons(now))));
  }
  EXPECT_EQ(files, 5);
}

// Files written before 3.16 (testdata/golden/v3.15/: the goldens whose comments the encoder now codes
// in the coded comments section, as plain lines in the comments section) decode forever, to the mesh
// and comment lines today's files of the same meshes decode to.
TEST(Golden, CommentFilesBefore316StillDecode) {
  int files = 0;
  for (const auto& e : fs::directory_iterator(kGolden + "/v3.15")) {
    if (e.path().extension() != ".qsp") continue;
    const std::string name = e.path().stem().string();
    SCOPED_TRACE(name);
    ++files;
    const std::string old = slurp(e.path().string()), now = slurp(kGolden + "/" + name + ".qsp");
    EXPECT_LT(old[9], kFormatMinorCodedComments);
    EXPECT_NE(container::parse(old).find(container::kTagComments), nullptr);
    EXPECT_NE(container::parse(now).find(container::kTagCodedComments), nullptr);
    EXPECT_EQ(file_comments(old), leading_comments(slurp(kGolden + "/" + name + ".obj")));
    EXPECT_EQ(file_comments(old), file_comments(now));
    EXPECT_EQ(write_obj_mesh(from_polygon_mesh(decode_polygons(old))),
              write_obj_mesh(from_polygon_mesh(decode_polygons(now))));
  }
  EXPECT_EQ(files, 1);
}

// Files written before 3.17 (testdata/golden/v3.16/: the goldens whose positions mirror prediction
// now codes) decode forever, to the mesh, attributes and comments today's files of the same meshes
// decode to.
TEST(Golden, FilesBeforeMirrorPredictionStillDecode) {
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(kGolden + "/v3.16")) {
    if (e.path().extension() != ".qsp") continue;
    const std::string name = fs::relative(e.path(), kGolden + "/v3.16").replace_extension().string();
    SCOPED_TRACE(name);
    ++files;
    const std::string old = slurp(e.path().string()), now = slurp(kGolden + "/" + name + ".qsp");
    EXPECT_LT(old[9], kFormatMinorMirror);
    EXPECT_EQ(now[9], kFormatMinorMirror);
    EXPECT_EQ(container::parse(old).find(container::kTagSymmetry), nullptr);
    EXPECT_NE(container::parse(now).find(container::kTagSymmetry), nullptr);
    EXPECT_EQ(write_obj_mesh(from_polygon_mesh(decode_polygons(old))),
              write_obj_mesh(from_polygon_mesh(decode_polygons(now))));
  }
  EXPECT_EQ(files, 5);
}

TEST(Golden, EveryToolCombinationIsPinned) {
  fs::create_directories(kTools);
  std::map<std::uint8_t, int> seen;
  for (const ToolGolden& g : tool_goldens()) {
    SCOPED_TRACE(g.name);
    const std::string bytes = encode_tool_golden(g);
    const std::string path = kTools + "/" + g.name + ".qsp";
    if (updating()) spit(path, bytes);
    ASSERT_TRUE(fs::exists(path));
    EXPECT_EQ(bytes, slurp(path)) << "the encoder's output changed: a format change needs a version bump";
    const FileInfo info = inspect(slurp(path));
    EXPECT_EQ(info.geometry_tools, g.tools);
    EXPECT_EQ(info.level, kMaxLevel);
    ++seen[info.geometry_tools];
    const QuadMesh got = decode(slurp(path)), want = decode(slurp(kGolden + "/" + g.mesh + ".qsp"));
    EXPECT_EQ(got.quads, want.quads);
    EXPECT_EQ(got.positions, want.positions);
  }
  EXPECT_EQ(seen.size(), std::size_t{geometry_tool::kAll} + 1);
  std::map<CodingOrder, int> orders;
  int costly = 0;
  for (const auto& name : golden_names()) {
    const FileInfo info = inspect(slurp(kGolden + "/" + name + ".qsp"));
    ++orders[info.geometry_order];
    costly += (info.geometry_tools & geometry_tool::kLogisticMixing) != 0;
  }
  EXPECT_GE(orders[CodingOrder::kPatch], 5);
  EXPECT_GE(orders[CodingOrder::kLayout], 1);
  EXPECT_GE(costly, 5);
}

// Every strict prefix and every single-bit flip of every golden file is refused with a typed error.
TEST(Golden, EveryPrefixAndBitFlipIsRefused) {
  for (const auto& path : golden_paths()) {
    SCOPED_TRACE(path);
    const std::string good = slurp(path);
    for (std::size_t n = 0; n < good.size(); ++n) {
      try {
        decode_polygons(std::string_view(good).substr(0, n));
        ADD_FAILURE() << "prefix of " << n << " bytes accepted";
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::kFormat) << n << ": " << e.what();
      }
    }
    for (std::size_t bit = 0; bit < 8 * good.size(); ++bit) {
      std::string bad = good;
      bad[bit / 8] = static_cast<char>(bad[bit / 8] ^ (1 << (bit % 8)));
      try {
        decode_polygons(bad);
        ADD_FAILURE() << "flip of bit " << bit << " accepted";
      } catch (const Error& e) {
        EXPECT_TRUE(e.code() == ErrorCode::kFormat || e.code() == ErrorCode::kVersion ||
                    e.code() == ErrorCode::kChecksum)
            << bit << ": " << error_name(e.code()) << ": " << e.what();
      }
    }
  }
}

// ---- Crafted files ----

std::string section(std::uint8_t tag, std::string_view payload) {
  std::string s;
  container::put_section(s, tag, payload);
  return s;
}

struct Parts {
  std::uint8_t major = 0, minor = 0, encoder = 0;
  std::string counts, topology, geometry;  // section payloads
};

// Splits a file the encoder wrote for a small mesh (1-byte size field, the three sections in order).
Parts split(const std::string& f) {
  const container::File file = container::parse(f);
  Parts p;
  p.major = file.major, p.minor = file.minor, p.encoder = static_cast<std::uint8_t>(f[10]);
  p.counts = std::string(file.find(container::kTagCounts)->payload);
  p.topology = std::string(file.find(container::kTagTopology)->payload);
  p.geometry = std::string(file.find(container::kTagGeometry)->payload);
  return p;
}

std::string seal(const Parts& p, std::string_view sections) {
  return container::seal(p.major, p.minor, p.encoder, sections);
}

std::string assemble(const Parts& p) {
  return seal(p, section(1, p.counts) + section(2, p.topology) + section(3, p.geometry));
}

// The crafted invalid files: name -> (bytes, expected code, expected message substring).
struct Crafted {
  std::string bytes, code, message;
};

std::map<std::string, Crafted> crafted() {
  const std::string good = slurp(kGolden + "/quad.qsp");
  const Parts p = split(good);
  std::map<std::string, Crafted> out;
  out["qsp_empty"] = {"", "format", "truncated"};
  out["qsp_truncated"] = {
      good.substr(0, 40), "format",
      "truncated: header declares " + std::to_string(good.size()) + " bytes, file has 40"};
  std::string bad_magic = good;
  bad_magic[1] = 'X';
  out["qsp_bad_magic"] = {bad_magic, "format", "bad magic number"};
  std::string crlf = good;
  crlf.erase(4, 1);  // CR LF -> LF, as a text-mode transfer would
  out["qsp_line_endings_converted"] = {crlf, "format", "line-ending bytes were changed"};
  std::string seven = good;
  seven[0] = static_cast<char>(0x09);
  out["qsp_high_bit_stripped"] = {seven, "format", "7-bit transfer"};
  Parts newer = p;
  newer.major = kFormatMajor + 1;
  out["qsp_newer_major"] = {assemble(newer), "version",
                            "file is .qsp format " + std::to_string(kFormatMajor + 1) + "." +
                                std::to_string(p.minor) + "; this qsp reads format " +
                                std::to_string(kFormatMajor) + ".x (upgrade qsp)"};
  Parts development = p;
  development.major = 2, development.minor = 2;
  out["qsp_development_version"] = {
      assemble(development), "version",
      "file is .qsp format 2.2, a development version (before 3.0) that this qsp "
      "does not read"};
  std::string flipped = good;
  flipped[40] = static_cast<char>(flipped[40] ^ 0x04);
  out["qsp_checksum_mismatch"] = {flipped, "checksum", "checksum mismatch"};
  Parts reserved = p;
  reserved.encoder = 0x19;
  out["qsp_reserved_encoder_bit"] = {assemble(reserved), "format", "reserved encoder byte bits are set"};
  Parts level = p;
  level.encoder = 10;
  out["qsp_level_out_of_range"] = {assemble(level), "format", "compression level 10 is not 0 to 9"};
  Parts reserved2 = p;
  reserved2.counts.back() = 0x40;
  out["qsp_reserved_counts_bit"] = {assemble(reserved2), "format", "reserved counts flag bits are set"};
  out["qsp_trailing_bytes"] = {good + std::string("\0\0\0", 3), "format", "3 trailing bytes"};
  {
    std::string sec = section(1, p.counts) + section(2, p.topology);
    sec += std::string(1, '\x03') + std::string(1, '\x7f') + p.geometry;  // geometry claims 127 bytes
    out["qsp_section_longer_than_file"] = {
        seal(p, sec), "format",
        "section declares 127 bytes but only " + std::to_string(p.geometry.size()) + " remain"};
  }
  {
    std::string counts;
    put_varint(counts, 1000000000);
    put_varint(counts, 100000000);
    counts += std::string("\x01\x00\x00", 3);
    Parts huge = p;
    huge.counts = counts;
    out["qsp_huge_counts"] = {assemble(huge), "limit", "vertex count 1000000000 exceeds the limit 67108864"};
    counts.clear();
    put_varint(counts, 5000);
    put_varint(counts, 5000);
    counts += std::string("\x01\x00\x00", 3);
    huge.counts = counts;
    out["qsp_counts_larger_than_content"] = {
        assemble(huge), "format",
        "topology describes 1 faces and 4 referenced vertices, the counts section 5000 and 5000"};
  }
  {
    Parts more = p;
    more.counts[0] = 5;  // 5 vertices, but the topology has 4 and no unreferenced vertex
    out["qsp_counts_mismatch"] = {
        assemble(more), "format",
        "topology describes 1 faces and 4 referenced vertices, the counts section 1 and 5"};
  }
  {
    // A required section of a newer minor version: "upgrade qsp". The same tag in a file of this
    // version cannot come from a correct encoder.
    const std::string sections =
        section(1, p.counts) + section(2, p.topology) + section(3, p.geometry) + section(16, "x");
    Parts newer_minor = p;
    newer_minor.minor = kFormatMinor + 1;
    out["qsp_unknown_required_section_newer_minor"] = {
        seal(newer_minor, sections), "version",
        "section 0x10 is required but unknown to this qsp, which reads format 3." +
            std::to_string(kFormatMinor) + " (upgrade qsp)"};
    out["qsp_unknown_required_section"] = {seal(p, sections), "format",
                                           "section 0x10 is required but unknown to this qsp"};
    // A section of a later minor version in a file that says it is the one before: 3.3's face labels,
    // 3.4's subdivision tags, 3.5's normals, 3.6's exact positions, 3.8's colours, 3.12's interior
    // positions, 3.13's exact values, 3.14's properties.
    struct Later {
      const char* name;
      std::uint8_t tag, minor;
      const char* message;
    };
    for (const Later& l :
         {Later{"qsp_labels_section_in_3_2", 7, 2,
                "section 0x07 (face labels) is format 3.3's, and the file says it is 3.2"},
          Later{"qsp_tags_section_in_3_3", 8, 3,
                "section 0x08 (subdivision tags) is format 3.4's, and the file says it is 3.3"},
          Later{"qsp_normals_section_in_3_4", 9, 4,
                "section 0x09 (normals) is format 3.5's, and the file says it is 3.4"},
          Later{"qsp_exact_section_in_3_5", 10, 5,
                "section 0x0a (exact positions) is format 3.6's, and the file says it is 3.5"},
          Later{"qsp_colors_section_in_3_7", 11, 7,
                "section 0x0b (colours) is format 3.8's, and the file says it is 3.7"},
          Later{"qsp_interior_section_in_3_11", 12, 11,
                "section 0x0c (interior positions) is format 3.12's, and the file says it is 3.11"},
          Later{"qsp_exact_values_section_in_3_12", 13, 12,
                "section 0x0d (exact values) is format 3.13's, and the file says it is 3.12"},
          Later{"qsp_properties_section_in_3_13", 14, 13,
                "section 0x0e (properties) is format 3.14's, and the file says it is 3.13"}}) {
      Parts earlier = p;
      earlier.minor = l.minor;
      out[l.name] = {seal(earlier, section(1, p.counts) + section(2, p.topology) + section(3, p.geometry) +
                                       section(l.tag, "x")),
                     "format", l.message};
    }
    // Format 3.1's polygons section in a file that says it is 3.0.
    out["qsp_polygons_section_in_3_0"] = {
        seal(p, section(1, p.counts) + section(2, p.topology) + section(3, p.geometry) + section(5, "x")),
        "format", "section 0x05 (polygons) is format 3.1's, and the file says it is 3.0"};
  }
  {
    // A polygon file (format 3.12): a 2x1 grid whose right cell is two triangles, its polygons section
    // replaced by what no encoder writes.
    PolygonMesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
    m.face_offsets = {0, 4, 7, 10};
    m.corners = {0, 1, 4, 3, 1, 2, 5, 1, 5, 4};
    const std::string poly_file = encode_polygons(m);
    const container::File poly = container::parse(poly_file);
    std::string quads;
    for (std::uint8_t tag : {container::kTagCounts, container::kTagTopology, container::kTagGeometry})
      quads += section(tag, poly.find(tag)->payload);
    // Its two triangles' far corners are interior vertices, which the geometry section codes (3.12).
    Parts v312 = p;
    v312.minor = kFormatMinorInterior;
    auto with = [&](std::uint64_t interior, std::uint64_t regions, std::uint64_t groups,
                    const std::string& stream) {
      std::string payload;
      for (std::uint64_t x : {interior, regions, groups, std::uint64_t{stream.size()}})
        put_varint(payload, x);
      return seal(v312, quads + section(5, payload + stream) +
                            section(container::kTagInterior, poly.find(container::kTagInterior)->payload));
    };
    out["qsp_polygons_interior_past_the_format"] = {
        with(std::uint64_t{1} << 31, 1, 0, "x"), "format",
        "polygons section: more vertices than the format's 2^31 - 1"};
    out["qsp_polygons_regions_past_the_stream"] = {with(0, 1u << 20, 0, "x"), "format",
                                                   "polygons section: more regions than the stream can hold"};
    out["qsp_polygons_empty_stream"] = {with(0, 1, 0, ""), "format",
                                        "polygons section: regions: region 0, face 0: a face of degree"};
  }
  {
    // The texture coordinates section's flag bit 7 (3.16's hints) in a file that says 3.15.
    const std::string cylinder = slurp(kGolden + "/v3.16/texcoords/cylinder_seam_uv12.qsp");
    const container::File uv = container::parse(cylinder);
    std::string sections;
    for (const container::Section& s : uv.sections) container::put_section(sections, s.tag, s.payload);
    out["qsp_texcoords_hints_in_3_15"] = {
        container::seal(uv.major, kFormatMinorSeamHints - 1, uv.level, sections), "format",
        "flag bit 7 (hints from the faces across) is format 3.16's, and the file says it is 3.15"};
  }
  {
    // The texture coordinates' mirror prediction (flag bit 5, 3.18): in a file that says 3.17, in a file
    // without a symmetry section, and with a sign bit beyond the section's two components.
    const std::string hull = slurp(kGolden + "/mirror/hull_uv12.qsp");
    const container::File f = container::parse(hull);
    const std::string uv(f.find(container::kTagTexcoords)->payload);
    EXPECT_TRUE(uv[0] & 0x20) << "hull_uv12's texture coordinates use mirror prediction";
    std::string sections;
    for (const container::Section& s : f.sections) container::put_section(sections, s.tag, s.payload);
    out["qsp_texcoords_mirror_in_3_17"] = {
        container::seal(f.major, kFormatMinorTexcoordMirror - 1, f.level, sections), "format",
        "flag bit 5 (mirror prediction) is format 3.18's, and the file says it is 3.17"};
    const std::string grid = slurp(kGolden + "/texcoords/bent_grid_uv12.qsp");
    std::string flagged(container::parse(grid).find(container::kTagTexcoords)->payload);
    flagged[0] = static_cast<char>(flagged[0] | 0x20);
    out["qsp_texcoords_mirror_without_symmetry"] = {
        container::with_section(grid, container::kTagTexcoords, flagged, kFormatMinorTexcoordMirror),
        "format", "flag bit 5 (mirror prediction) without a symmetry section"};
    // The signs byte follows the flags, the two counts (varints) and the two modes.
    ByteReader r(uv, 0, "texture coordinates section");
    (void)r.u8("flags"), (void)r.varint("count"), (void)r.varint("unreferenced");
    std::string signs = uv;
    signs[r.pos() + 2] = static_cast<char>(signs[r.pos() + 2] | 0x04);
    out["qsp_texcoords_mirror_sign_bits"] = {
        container::with_section(hull, container::kTagTexcoords, signs, f.minor), "format",
        "mirror sign bits beyond the 2 components"};
  }
  {
    // The coded comments section (3.16, optional): its stream cut short, a text length past what its
    // stream can hold or past 2^20, 2^16 + 1 lines, a CR decoded inside a line, the section in a 3.15
    // file, beside a comments section.
    const std::string required = section(1, p.counts) + section(2, p.topology) + section(3, p.geometry);
    const std::string coded =
        encode_coded_comments_section({" Copyright (C) 2020 somebody", " Copyright (C) 2021 somebody else"});
    Parts v316 = p, v315 = p;
    v316.minor = kFormatMinorCodedComments;
    v315.minor = kFormatMinorCodedComments - 1;
    out["qsp_coded_comments_truncated"] = {
        seal(v316, required + section(container::kTagCodedComments, coded.substr(0, coded.size() - 3))),
        "format", "coded comments section ends too early"};
    std::string huge;
    put_varint(huge, 1024 * (coded.size() - 1 + 8) + 1);
    out["qsp_coded_comments_length_past_stream"] = {
        seal(v316, required + section(container::kTagCodedComments, huge + coded.substr(1))), "format",
        "coded comments section: text length " + std::to_string(1024 * (coded.size() - 1 + 8) + 1) +
            " is more than the " + std::to_string(1024 * (coded.size() - 1 + 8)) + " bytes a stream of " +
            std::to_string(coded.size() - 1) + " bytes can hold"};
    std::string past;
    put_varint(past, kCodedCommentsMaxText + 1);
    out["qsp_coded_comments_text_past_2_20"] = {
        seal(v316, required + section(container::kTagCodedComments, past + coded.substr(1))), "format",
        "coded comments section: text length 1048577 is more than the format's 1048576 bytes"};
    out["qsp_coded_comments_too_many_lines"] = {
        seal(v316, required + section(container::kTagCodedComments,
                                      encode_coded_comments_section(
                                          std::vector<std::string>(kCodedCommentsMaxLines + 1)))),
        "format",
        "coded comments section: the text's byte 65535 begins line 65537, past the format's 65536 lines"};
    out["qsp_coded_comments_cr"] = {
        seal(v316,
             required + section(container::kTagCodedComments, encode_coded_comments_section({"a", "b\rc"}))),
        "format", "coded comments section: the text's byte 3 is a CR"};
    out["qsp_coded_comments_in_3_15"] = {
        seal(v315, required + section(container::kTagCodedComments, coded)), "format",
        "section 0x85 (coded comments) is format 3.16's, and the file says it is 3.15"};
    out["qsp_coded_comments_beside_comments"] = {
        seal(v316, required + section(container::kTagComments, std::string("\x01\x01x", 3)) +
                       section(container::kTagCodedComments, coded)),
        "format", "section 0x85 (coded comments) beside section 0x81 (comments)"};
  }
  out["qsp_missing_geometry"] = {seal(p, section(1, p.counts) + section(2, p.topology)), "format",
                                 "required section 3 (geometry) is missing"};
  out["qsp_repeated_section"] = {
      seal(p,
           section(1, p.counts) + section(2, p.topology) + section(2, p.topology) + section(3, p.geometry)),
      "format", "section 0x02 after section 0x02 (sections come in increasing tag order, each once)"};
  out["qsp_invalid_section_tag"] = {
      seal(p, section(1, p.counts) + section(2, p.topology) + section(3, p.geometry) + section(0x80, "")),
      "format", "invalid section tag 0x80"};
  {
    Parts overlong = p;
    overlong.counts = std::string("\x84\x00", 2) + p.counts.substr(1);
    out["qsp_overlong_varint"] = {assemble(overlong), "format", "vertex count is not minimally encoded"};
  }
  {
    // Mirror prediction (3.17): geometry tool bit 5 and the symmetry section. hull_q14 is one 16x8 grid
    // of faces, symmetric, its one seed mapping face 0 to a face on the boundary too.
    const std::string hull = slurp(kGolden + "/mirror/hull_q14.qsp");
    const Parts h = split(hull);
    EXPECT_TRUE(h.geometry[0] & 0x20) << "hull_q14's geometry uses mirror prediction";
    const std::string required = section(1, h.counts) + section(2, h.topology);
    auto with = [&](const Parts& at, std::string_view geometry, std::string_view symmetry) {
      return seal(at, required + section(3, geometry) + section(container::kTagSymmetry, symmetry));
    };
    const std::string symmetry(container::parse(hull).find(container::kTagSymmetry)->payload);
    out["qsp_mirror_without_symmetry_section"] = {seal(h, required + section(3, h.geometry)), "format",
                                                  "mirror prediction without a symmetry section"};
    std::string plain = h.geometry;
    plain[0] = static_cast<char>(plain[0] & ~0x20);
    out["qsp_symmetry_without_mirror"] = {with(h, plain, symmetry), "format",
                                          "symmetry section: the geometry section does not predict by it"};
    Parts v316 = h;
    v316.minor = kFormatMinorMirror - 1;
    out["qsp_symmetry_in_3_16"] = {with(v316, h.geometry, symmetry), "format",
                                   "section 0x0f (symmetry) is format 3.17's, and the file says it is 3.16"};
    // Seeds: face 128 of 128 faces; a second seed giving face 0 another turn; face 0 (on the boundary)
    // onto face 17 (inside: row 1, column 1); axis 3.
    const auto seeds = [](std::initializer_list<std::array<std::uint32_t, 4>> list) {
      std::string s;
      put_varint(s, list.size());
      for (const auto& [f, g, turn, axis] : list) {
        put_varint(s, f);
        put_varint(s, g);
        s += static_cast<char>(turn | axis << 2);
      }
      return s;
    };
    out["qsp_mirror_seed_out_of_range"] = {with(h, h.geometry, seeds({{128, 0, 0, 0}})), "format",
                                           "symmetry section: seed face out of range"};
    const MirrorSeed seed = decode_symmetry(symmetry, 0, 128).at(0);
    const std::uint32_t image = seed.image, turn = seed.turn;
    out["qsp_mirror_face_with_two_images"] = {
        with(h, h.geometry, seeds({{0, image, turn, 0}, {0, image, (turn + 1) & 3, 0}})), "format",
        "symmetry section (at byte offset"};
    out["qsp_mirror_boundary_onto_inside"] = {with(h, h.geometry, seeds({{0, 17, 0, 0}})), "format",
                                              "and its image: one on the boundary"};
    out["qsp_mirror_axis_out_of_range"] = {with(h, h.geometry, seeds({{0, image, turn, 3}})), "format",
                                           "symmetry section: seed axis out of range"};
  }
  {
    // Before 3.12 a polygons section ends in its own geometry stream of the interior positions (its byte
    // 18 here is that stream's tools byte), which mirror prediction never codes: bit 5 stays reserved there.
    const std::string old = slurp(kGolden + "/v3.11/polygons/polygons_mixed.qsp");
    const container::File f = container::parse(old);
    std::string poly(f.find(container::kTagPolygons)->payload);
    poly[18] = static_cast<char>(poly[18] | 0x20);
    out["qsp_polygons_interior_mirror_bit"] = {
        container::with_section(old, container::kTagPolygons, poly, f.minor), "format",
        "the interior positions use mirror prediction"};
  }
  // The geometry tools byte: bit 5 is mirror prediction (3.17), which a file without a symmetry section
  // cannot use; bits 6 and 7 are reserved.
  {
    Parts mirror = p;
    mirror.geometry[0] = static_cast<char>(mirror.geometry[0] | 0x20);
    out["qsp_reserved_geometry_tool_bit_5"] = {
        assemble(mirror), "format", "geometry section: mirror prediction without a symmetry section"};
  }
  for (int bit = 6; bit < 8; ++bit) {
    Parts future = p;
    future.geometry[0] = static_cast<char>(future.geometry[0] | (1 << bit));
    out["qsp_reserved_geometry_tool_bit_" + std::to_string(bit)] = {
        assemble(future), "format", "geometry section: reserved tool bits are set"};
  }
  {
    Parts bits = p;
    bits.geometry[1] = 31;
    out["qsp_geometry_bits_out_of_range"] = {assemble(bits), "format",
                                             "geometry section: quantization bits 31 out of range"};
  }
  {
    Parts junk = p;
    junk.topology += '\0';
    out["qsp_topology_trailing_byte"] = {assemble(junk), "format",
                                         "topology section does not end as the encoder ends it"};
  }
  return out;
}

TEST(Invalid, CraftedFilesArePinnedAndRefused) {
  for (const auto& [name, c] : crafted()) {
    SCOPED_TRACE(name);
    std::string path = kInvalid + "/" + name + ".qsp";
    if (updating()) {
      spit(path, c.bytes);
      spit(kInvalid + "/" + name + ".expect", "code=" + c.code + "\nmessage=" + c.message + "\n");
    }
    EXPECT_EQ(slurp(path), c.bytes);
  }
}

TEST(Invalid, EveryQspIsRefusedWithItsExpectedError) {
  int seen = 0;
  for (const auto& e : fs::directory_iterator(kInvalid)) {
    if (e.path().extension() != ".qsp") continue;
    ++seen;
    SCOPED_TRACE(e.path().string());
    auto expect = testing::read_expect(fs::path(e.path()).replace_extension(".expect"));
    ASSERT_TRUE(expect.count("code") && expect.count("message"));
    try {
      // Reads every 3.x file, polygon files included, and then the comment lines.
      (void)decode_polygons(slurp(e.path().string()));
      (void)file_comments(slurp(e.path().string()));
      ADD_FAILURE() << "accepted";
    } catch (const Error& err) {
      EXPECT_EQ(error_name(err.code()), expect["code"]) << err.what();
      EXPECT_NE(std::string(err.what()).find(expect["message"]), std::string::npos) << err.what();
    }
  }
  EXPECT_GE(seen, 25);
}

TEST(Invalid, UnknownOptionalSectionsAreSkipped) {
  const Parts p = split(slurp(kGolden + "/quad.qsp"));
  std::string with_extra = seal(p, section(1, p.counts) + section(2, p.topology) + section(3, p.geometry) +
                                       section(0x81, "future data") + section(0xA0, ""));
  QuadMesh m = decode(with_extra);
  EXPECT_EQ(m.face_count(), 1u);
  FileInfo info = inspect(with_extra);
  EXPECT_EQ(info.comment_bytes, 2u + 11u) << "0x81 is the comments section, its text whatever it holds";
  EXPECT_EQ(info.other_bytes, 2u);
}

// A file of a newer minor version without the sections that minor may have added reads as its own.
TEST(Invalid, NewerMinorVersionIsRead) {
  Parts p = split(slurp(kGolden + "/quad.qsp"));
  p.minor = 7;
  EXPECT_EQ(decode(assemble(p)).face_count(), 1u);
}

// ---- The spec's worked example ----

// The hex dump between "<!-- example: NAME -->" and the closing fence of the next code block.
std::string spec_example(const std::string& name) {
  std::string md = slurp(std::string(QSP_TESTDATA_DIR) + "/../format-spec/qsp_format.md");
  auto at = md.find("<!-- example: " + name + " -->");
  if (at == std::string::npos) return {};
  auto open = md.find("```", at);
  auto body = md.find('\n', open) + 1;
  auto close = md.find("```", body);
  std::string out;
  std::istringstream in(md.substr(body, close - body));
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find('#'));  // comments after '#'
    std::istringstream words(line);
    std::string w;
    while (words >> w) out.push_back(static_cast<char>(std::stoi(w, nullptr, 16)));
  }
  return out;
}

TEST(Spec, WorkedExampleDecodes) {
  std::string bytes = spec_example("quad.qsp");
  ASSERT_FALSE(bytes.empty()) << "format-spec/qsp_format.md lost its worked example";
  EXPECT_EQ(bytes, slurp(kGolden + "/quad.qsp"));
  QuadMesh m = decode(bytes);
  EXPECT_EQ(m.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
  EXPECT_EQ(m.quads, (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EncodeOptions best;
  best.level = kMaxLevel;
  EXPECT_EQ(encode(m, best), bytes);
}

}  // namespace
}  // namespace qsp
