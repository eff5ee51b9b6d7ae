// The polygons section (format 3.1): any polygon mesh through bytes and back, compared by the test's
// own reading of the input (tests/support/polygon.h) and of the output, not by the codec's maps;
// renumbered copies give identical bytes; all-quad manifold meshes keep their 3.0 bytes; cut and
// flipped files are refused with a format error or decode to a valid mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bytes.h"
#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/submesh.h"
#include "support/corpus.h"
#include "support/minor.h"
#include "support/polygon.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::Grid;
using testing::Poly;

// All at the origin where a case has no positions: a renumbered copy must give the same bytes.
PolygonMesh to_mesh(const Poly& p) { return testing::to_mesh(p, 0.0f); }

// Distinct positions on a lattice, so that vertices can be named by position.
Poly with_positions(Poly p) {
  p.positions.resize(3 * std::size_t{p.nv});
  for (std::uint32_t v = 0; v < p.nv; ++v) {
    p.positions[3 * v] = static_cast<float>(v % 7);
    p.positions[3 * v + 1] = static_cast<float>(v / 7 % 7);
    p.positions[3 * v + 2] = static_cast<float>(v / 49);
  }
  return p;
}

// A 3x3 quad grid whose middle cell is a fan of four triangles around a vertex no quad has (the last
// vertex), with with_positions' lattice positions.
Poly fan_in_a_hole() {
  Grid g = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? '.' : 'q'; });
  const std::uint32_t c = g.p.nv++;
  g.p.face({g.id(1, 1), g.id(2, 1), c});
  g.p.face({g.id(2, 1), g.id(2, 2), c});
  g.p.face({g.id(2, 2), g.id(1, 2), c});
  g.p.face({g.id(1, 2), g.id(1, 1), c});
  return with_positions(g.p);
}

using Point = std::array<float, 3>;

// Each face as the cyclic sequence of its corners' positions, rotated to start at its smallest, sorted:
// equal for two meshes exactly when they have the same faces (corner cycles kept) up to renumbering,
// where positions tell vertices apart; with repeated positions it still compares faces and positions.
std::vector<std::vector<Point>> faces_by_position(const std::vector<std::uint32_t>& offsets,
                                                  const std::vector<std::uint32_t>& corners,
                                                  const std::vector<float>& positions) {
  std::vector<std::vector<Point>> faces;
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f) {
    std::vector<Point> face;
    for (std::uint32_t c = offsets[f]; c < offsets[f + 1]; ++c) {
      const float* x = &positions[3 * std::size_t{corners[c]}];
      face.push_back({x[0], x[1], x[2]});
    }
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
    faces.push_back(std::move(face));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

std::vector<Point> sorted_points(const std::vector<float>& positions) {
  std::vector<Point> out;
  for (std::size_t i = 0; i + 2 < positions.size(); i += 3)
    out.push_back({positions[i], positions[i + 1], positions[i + 2]});
  std::sort(out.begin(), out.end());
  return out;
}

// What decode_polygons promises of anything it accepts: faces of degree 3 or more on its vertices, none
// repeating a vertex.
void expect_valid(const PolygonMesh& m, const std::string& what) {
  ASSERT_FALSE(m.face_offsets.empty()) << what;
  ASSERT_EQ(m.face_offsets.back(), m.corners.size()) << what;
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    ASSERT_GE(m.face_offsets[f + 1] - m.face_offsets[f], 3u) << what << " face " << f;
    std::vector<std::uint32_t> face(m.corners.begin() + m.face_offsets[f],
                                    m.corners.begin() + m.face_offsets[f + 1]);
    for (std::uint32_t v : face) ASSERT_LT(v, m.vertex_count()) << what << " face " << f;
    std::sort(face.begin(), face.end());
    ASSERT_TRUE(std::adjacent_find(face.begin(), face.end()) == face.end()) << what << " face " << f;
  }
}

// Encodes, decodes, and compares with the input: same vertex count, same positions, same faces.
std::string expect_round_trip(const Poly& p, const std::string& what, const EncodeOptions& o = {}) {
  const PolygonMesh in = to_mesh(p);
  const std::string bytes = encode_polygons(in, o);
  const PolygonMesh out = decode_polygons(bytes);
  expect_valid(out, what);
  EXPECT_EQ(out.vertex_count(), in.vertex_count()) << what;
  EXPECT_EQ(out.face_count(), in.face_count()) << what;
  EXPECT_TRUE(sorted_points(out.positions) == sorted_points(in.positions)) << what << ": positions differ";
  EXPECT_TRUE(faces_by_position(out.face_offsets, out.corners, out.positions) ==
              faces_by_position(in.face_offsets, in.corners, in.positions))
      << what << ": faces differ";
  return bytes;
}

// The sections of a file, without its header and checksum.
std::string body_of(const std::string& file) {
  const container::File f = container::parse(file);
  return file.substr(f.sections.front().offset,
                     file.size() - container::kChecksumBytes - f.sections.front().offset);
}

// ---- Hand-made cases.

TEST(PolygonCodec, HandCasesRoundTripAndAreCanonical) {
  for (const testing::PolyCase& c : testing::hand_polygon_cases()) {
    const Poly p = with_positions(c.p);
    const std::string bytes = expect_round_trip(p, c.name);
    EXPECT_EQ(bytes[9], testing::minor_of_file_with(bytes, 1)) << c.name << ": a polygon file is format 3.1";
    // The interior positions section (3.12) exactly where a vertex with faces is in no quad.
    std::vector<int> in_quad(p.nv), in_face(p.nv);
    for (std::uint32_t f = 0; f < p.face_count(); ++f)
      for (std::uint32_t k = p.offsets[f]; k < p.offsets[f + 1]; ++k)
        in_face[p.corners[k]] = 1, in_quad[p.corners[k]] |= p.degree(f) == 4;
    EXPECT_EQ(inspect(bytes).interior_positions > 0, in_face != in_quad) << c.name;
    EXPECT_TRUE(holds_polygons(bytes)) << c.name;
    for (std::uint32_t seed : {5u, 6u})
      EXPECT_EQ(encode_polygons(to_mesh(testing::shuffled(p, seed))), bytes) << c.name;
  }
}

TEST(PolygonCodec, ManifoldQuadMeshKeepsItsFormat30Bytes) {
  const Poly p = with_positions(Grid::make(4, 3, [](int, int) { return 'q'; }).p);
  const PolygonMesh m = to_mesh(p);
  const std::string bytes = encode_polygons(m);
  EXPECT_EQ(bytes, encode(QuadMesh{m.positions, m.corners}));
  EXPECT_EQ(bytes[9], 0);
  EXPECT_FALSE(holds_polygons(bytes));
  const PolygonMesh back = decode_polygons(bytes);
  EXPECT_EQ(back.corners, decode(bytes).quads);
}

TEST(PolygonCodec, TriangleMeshOfFreeRegions) {
  const Poly p = with_positions(Grid::make(5, 4, [](int, int) { return 't'; }).p);
  expect_round_trip(p, "triangle grid");
}

TEST(PolygonCodec, NgonWithInteriorVerticesAndQuantizedPositions) {
  Poly p = with_positions(testing::ngon_with_a_quad(40));
  expect_round_trip(p, "40-gon");
  // A triangle fan around an interior vertex in a quad grid's hole.
  Poly fan = fan_in_a_hole();
  const std::uint32_t c = fan.nv - 1;
  fan.positions[3 * c] = 1.5f, fan.positions[3 * c + 1] = 1.5f, fan.positions[3 * c + 2] = 0.25f;
  expect_round_trip(fan, "fan around an interior vertex");
  // Quantized: the same faces as lossless on the same numbering, positions within the grid's step.
  EncodeOptions q;
  q.quantize_bits = 10;
  const PolygonMesh exact = decode_polygons(encode_polygons(to_mesh(fan)));
  const PolygonMesh coarse = decode_polygons(encode_polygons(to_mesh(fan), q));
  EXPECT_EQ(coarse.face_offsets, exact.face_offsets);
  EXPECT_EQ(coarse.corners, exact.corners);
  ASSERT_EQ(coarse.positions.size(), exact.positions.size());
  for (std::size_t i = 0; i < exact.positions.size(); ++i)
    EXPECT_NEAR(coarse.positions[i], exact.positions[i], 6.0 / 1024) << i;
}

// inspect() splits the polygons section: its counts and region stream are connectivity, the positions
// of vertices no quad has geometry; the two parts make the section, found here by its own tag and length.
TEST(PolygonCodec, InspectSplitsThePolygonsSection) {
  const Poly pairs =
      with_positions(Grid::make(4, 3, [](int i, int j) { return i == 2 && j == 1 ? 't' : 'q'; }).p);
  const Poly fan = fan_in_a_hole();
  for (const auto& [poly, interior] : {std::pair{pairs, false}, {fan, true}}) {
    const std::string bytes = encode_polygons(to_mesh(poly));
    const FileInfo info = inspect(bytes);
    ASSERT_TRUE(info.polygons);
    std::uint64_t section = 0;
    for (const SectionInfo& si : info.sections)
      if (si.tag == 0x05) section = si.size;
    ASSERT_GT(section, 0u);
    EXPECT_EQ(info.polygon_connectivity_bytes, section);
    EXPECT_EQ(info.polygon_positions_bytes, 0u) << "from 3.12 the geometry section codes them";
    EXPECT_EQ(info.interior_positions > 0, interior) << "positions only where a vertex has no quad";
    EXPECT_EQ(info.header_bytes + info.connectivity_bytes + info.geometry_bytes + info.order_bytes +
                  info.other_bytes,
              bytes.size());
  }
}

TEST(PolygonCodec, NonManifoldAndMisorientedQuadMeshesRoundTrip) {
  // A fin: three quads on one edge.
  Poly fin = Grid::make(2, 1, [](int, int) { return 'q'; }).p;
  fin.nv += 2;
  fin.face({1, 4, fin.nv - 1, fin.nv - 2});
  expect_round_trip(with_positions(fin), "fin");
  // One clockwise quad in a grid.
  Poly flip = Grid::make(3, 3, [](int, int) { return 'q'; }).p;
  std::reverse(flip.corners.begin() + 16, flip.corners.begin() + 20);
  const std::string bytes = expect_round_trip(with_positions(flip), "flipped quad");
  EXPECT_TRUE(holds_polygons(bytes));
}

// --keep-order: the order section over all faces (rotations modulo each face's degree) gives back the
// input arrays exactly.
void expect_order_kept(const Poly& p, const std::string& what) {
  EncodeOptions o;
  o.keep_order = true;
  const PolygonMesh in = to_mesh(p);
  const std::string bytes = encode_polygons(in, o);
  const PolygonMesh out = decode_polygons(bytes);
  EXPECT_EQ(out.face_offsets, in.face_offsets) << what;
  EXPECT_EQ(out.corners, in.corners) << what;
  EXPECT_TRUE(out.positions == in.positions) << what;
}

TEST(PolygonCodec, KeepOrderRestoresTheInputNumbering) {
  for (const testing::PolyCase& c : testing::hand_polygon_cases()) {
    expect_order_kept(with_positions(c.p), c.name);
    expect_order_kept(with_positions(testing::shuffled(c.p, 9)), c.name + " shuffled");
  }
  expect_order_kept(with_positions(testing::ngon_with_a_quad(300)), "300-gon");
  // The order section of a polygon file is not a quad file's.
  EncodeOptions o;
  o.keep_order = true;
  const std::string bytes = encode_polygons(to_mesh(with_positions(testing::ngon_with_a_quad(7))), o);
  EXPECT_THROW((void)file_order(bytes), Error);
}

TEST(PolygonCodec, QuadReaderRefusesPolygonFiles) {
  const Poly p = with_positions(Grid::make(2, 2, [](int i, int) { return i ? 'q' : 't'; }).p);
  const std::string bytes = encode_polygons(to_mesh(p));
  try {
    (void)decode(bytes);
    ADD_FAILURE() << "decode() accepted a polygon file";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotQuad) << e.what();
  }
  // What the CLI asks before choosing a decoder: the container alone, checked as decode() checks it.
  EXPECT_TRUE(holds_polygons(bytes));
  std::string flipped = bytes;
  flipped[flipped.size() / 2] ^= 1;
  try {
    (void)holds_polygons(flipped);
    ADD_FAILURE() << "holds_polygons() took a file whose checksum does not match";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kChecksum) << e.what();
  }
  // Section 0x05 in a file that says it is 3.0 cannot come from a correct encoder.
  try {
    (void)decode_polygons(container::seal(3, 0, 0, body_of(bytes)));
    ADD_FAILURE() << "a 3.0 file with section 0x05 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFormat) << e.what();
    EXPECT_NE(std::string(e.what()).find("format 3.1"), std::string::npos) << e.what();
  }
}

// ---- Hostile bytes: every cut and every bit flip of the body, re-sealed so the checksum does not hide it.

void expect_clean(const std::string& bytes, const std::string& what, int& refused) {
  PolygonMesh m;
  try {
    m = decode_polygons(bytes);
  } catch (const Error& e) {
    EXPECT_NE(e.code(), ErrorCode::kInternal) << what << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << what << ": " << e.what();
    ++refused;
    return;
  }
  expect_valid(m, what);
}

TEST(PolygonCodec, EveryResealedBitFlipAndCutIsRefusedOrValid) {
  std::vector<std::pair<std::string, Poly>> cases;
  for (const testing::PolyCase& c : testing::hand_polygon_cases())
    if (c.name == "uv_sphere_poles" || c.name == "triangle_hole_in_a_grid" ||
        c.name == "notch_with_triangles")
      cases.emplace_back(c.name, with_positions(c.p));
  cases.emplace_back("triangles", with_positions(Grid::make(2, 2, [](int, int) { return 't'; }).p));
  ASSERT_GE(cases.size(), 3u);
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const auto& [name, p] = cases[k];
    EncodeOptions o;
    o.keep_order = k % 2 == 1;  // half of them with the order section over all faces
    const std::string file = encode_polygons(to_mesh(p), o);
    const std::string body = body_of(file);
    const auto minor = static_cast<std::uint8_t>(file[9]);  // 3.12 where a vertex is in no quad
    int refused = 0;
    for (std::size_t i = 0; i < body.size(); ++i) {
      for (int b = 0; b < 8; ++b) {
        std::string flipped = body;
        flipped[i] = static_cast<char>(flipped[i] ^ (1 << b));
        expect_clean(container::seal(3, minor, 0, flipped),
                     name + " flip " + std::to_string(i) + "." + std::to_string(b), refused);
      }
      expect_clean(container::seal(3, minor, 0, body.substr(0, i)), name + " cut " + std::to_string(i),
                   refused);
    }
    EXPECT_GT(refused, static_cast<int>(body.size())) << name;
    // Every prefix of the whole file is refused (truncated).
    for (std::size_t n = 0; n < file.size(); ++n)
      EXPECT_THROW((void)decode_polygons(file.substr(0, n)), Error) << n;
  }
}

// The decoder's limits: refs (interior vertices included) against max_vertices before anything is
// allocated by them, all faces against max_faces.
TEST(PolygonCodec, LimitsAreCheckedOnRefsAndAllFaces) {
  const std::string bytes = encode_polygons(to_mesh(fan_in_a_hole()));  // 17 vertices, 12 faces
  DecodeLimits l;
  l.max_vertices = 16;  // the quads' 16 vertices fit, the interior one does not
  try {
    (void)decode_polygons(bytes, l);
    ADD_FAILURE() << "accepted past max_vertices";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kLimit) << e.what();
  }
  l = {};
  l.max_faces = 11;  // the 8 quads fit, not the 4 triangles
  try {
    (void)decode_polygons(bytes, l);
    ADD_FAILURE() << "accepted past max_faces";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kLimit) << e.what();
  }
  l.max_faces = 12;
  l.max_vertices = 17;
  EXPECT_EQ(decode_polygons(bytes, l).face_count(), 12u);
}

// Large hostile shapes cost their size through the codec too (ctest's timeout would catch a quadratic
// coder): a 20,000-valence fan of alternating quads and triangles, a 50,000-gon on a quad.
TEST(PolygonCodec, HostileShapesCostTheirSize) {
  expect_round_trip(with_positions(testing::alternating_fan(20000)), "alternating fan");
  expect_round_trip(with_positions(testing::ngon_with_a_quad(50000)), "50,000-gon");
}

// ---- Corpus.

// Every corpus mesh (testdata/, ../shared/meshes and osd_shapes/: non-quad and non-manifold ones
// included) round-trips through bytes; renumbered copies of the smaller ones give identical bytes.
TEST(PolygonCodec, EveryCorpusMeshRoundTripsAndIsCanonical) {
  int meshes = 0, polygon_files = 0, renumbered = 0;
  for (const fs::path& path : testing::corpus()) {
    SCOPED_TRACE(path.string());
    const Poly p = testing::read_faces(path);
    if (!testing::cuttable(p)) continue;
    const std::string bytes = expect_round_trip(p, path.filename().string());
    polygon_files += holds_polygons(bytes);
    ++meshes;
    if (p.face_count() <= 20000) {
      EXPECT_EQ(encode_polygons(to_mesh(testing::shuffled(p, 3))), bytes) << "renumbered copy";
      expect_order_kept(p, path.filename().string());
      ++renumbered;
    }
  }
  EXPECT_GT(meshes, testing::shared_present() ? 130 : 20);
  // testdata/'s corpus is all quads (its polygon files are under invalid/, by history): without
  // ../shared the hand cases above carry the polygon section.
  EXPECT_GE(polygon_files, testing::shared_present() ? 21 : 0);
  EXPECT_GT(renumbered, testing::shared_present() ? 100 : 20);
}

// The polygons section's cost per non-quad face, beside Draco's -preserve_polygons (5.5-5.8 bits per
// face on real heads).
TEST(PolygonCodec, SectionBitsPerNonQuadFace) {
  QSP_NEEDS_SHARED();
  for (const std::string name : {"osd_catmark_bishop.obj", "pmp_suzanne.obj", "keenan_spot_control_mesh.obj",
                                 "osd_catmark_nonquads.obj"}) {
    const fs::path path = testing::shared_dir() / "meshes" / name;
    const Poly p = testing::read_faces(path);
    std::size_t non_quads = 0;
    for (std::uint32_t f = 0; f < p.face_count(); ++f) non_quads += p.degree(f) != 4;
    ASSERT_GT(non_quads, 0u) << name;
    for (const std::uint32_t bits : {14u, 0u}) {
      EncodeOptions o;
      o.quantize_bits = bits;
      const std::string bytes = encode_polygons(to_mesh(p), o);
      const container::File f = container::parse(bytes);
      const container::Section* s = f.find(container::kTagPolygons);
      ASSERT_NE(s, nullptr) << name;
      // The connectivity part: the four counts and the stream (the interior positions follow it).
      ByteReader counts(s->payload, s->payload_offset);
      std::uint64_t length = 0;
      for (int k = 0; k < 4; ++k) length = counts.varint("polygons count");
      const std::size_t connectivity = counts.pos() + length;
      std::printf(
          "%-30s %-8s %5zu non-quad faces  section %5zu bytes (connectivity %5zu)  %6.2f bits per non-quad "
          "face "
          "(connectivity %5.2f)  file %zu bytes\n",
          name.c_str(), bits ? "14 bits" : "lossless", non_quads, s->payload.size(), connectivity,
          8.0 * s->payload.size() / non_quads, 8.0 * connectivity / non_quads, bytes.size());
    }
  }
}

}  // namespace
}  // namespace qsp
