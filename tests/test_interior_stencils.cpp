// The stencils of a polygon mesh's interior vertices (format 3.12, qsp_format.md "Interior positions
// section"), on hand-checked fans: which neighbour is w, which is across the fan, in both coding orders.
#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>
#include <vector>

#include "codec_sections.h"
#include "qsp/codec.h"
#include "qsp/regions.h"

namespace qsp {
namespace {

// Output faces over `vertices` vertices, no glue (every ref its own vertex).
PolygonFaces faces_of(std::uint32_t vertices,
                      std::initializer_list<std::initializer_list<std::uint32_t>> fs) {
  PolygonFaces p;
  p.vertex_count = vertices;
  for (const auto& f : fs) {
    p.corners.insert(p.corners.end(), f.begin(), f.end());
    p.face_offsets.push_back(static_cast<std::uint32_t>(p.corners.size()));
  }
  for (std::uint32_t v = 0; v < vertices; ++v) p.ref_vertex.push_back(v);
  return p;
}

// A pole: vertex 8 in the middle of a ring 0..7 of layout vertices, eight triangles (i, i+1, 8).
// Around 8 each triangle has b = i+1 and a = i: the fan walks 1, 0, 7, 6, ..., 2 and closes, so w is
// 1 and the vertex across from it, four entries on, is 5.
TEST(InteriorStencils, APoleIsPredictedHalfWayAcrossItsRing) {
  const PolygonFaces pole =
      faces_of(9, {{0, 1, 8}, {1, 2, 8}, {2, 3, 8}, {3, 4, 8}, {4, 5, 8}, {5, 6, 8}, {6, 7, 8}, {7, 0, 8}});
  std::vector<Stencil> s = interior_stencils(pole, 8, {});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].w, 1u);
  EXPECT_EQ(s[0].far, 5u);
  EXPECT_EQ(s[0].far_dist, 1u);
  EXPECT_EQ(s[0].ww, kInvalid);
  EXPECT_EQ(s[0].s, kInvalid);
  // Patch order names coding positions: layout vertex v coded at position 7 - v.
  const std::vector<std::uint32_t> reversed{7, 6, 5, 4, 3, 2, 1, 0};
  s = interior_stencils(pole, 8, reversed);
  EXPECT_EQ(s[0].w, 6u);
  EXPECT_EQ(s[0].far, 2u);
}

// Half a ring (triangles 4 to 6 gone) leaves an open fan. Across an open fan is its last entry.
TEST(InteriorStencils, AnOpenFanIsPredictedBetweenItsEnds) {
  const PolygonFaces half = faces_of(9, {{0, 1, 8}, {1, 2, 8}, {2, 3, 8}, {7, 0, 8}});
  const std::vector<Stencil> s = interior_stencils(half, 8, {});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].w, 1u);
  // The walk from face 0: 1, 0, then (7, 0, 8) has b = 0: 7; nothing has b = 7. Open, last entry 7.
  EXPECT_EQ(s[0].far, 7u);
}

// Interior vertices in order: 8 is coded before 9, so 9 may lean on 8; 8's only neighbours besides 9
// are layout vertices. A vertex whose neighbours are all coded after it has an empty stencil.
TEST(InteriorStencils, LaterInteriorVerticesLeanOnEarlierOnes) {
  const PolygonFaces two = faces_of(10, {{8, 9, 0}, {9, 8, 1}});
  std::vector<Stencil> s = interior_stencils(two, 8, {});
  ASSERT_EQ(s.size(), 2u);
  // Around 8: face 0 gives b = 0, a = 9; face 1 (b = 9) gives a = 1. Open: 0, 9, 1. w = 0, across = 1.
  EXPECT_EQ(s[0].w, 0u);
  EXPECT_EQ(s[0].far, 1u);
  // Around 9 (position 9): face 0 gives b = 8, a = 0; face 1 has b = 1. Open: 8, 0. w = 8 (position 8).
  EXPECT_EQ(s[1].w, 8u);
  EXPECT_EQ(s[1].far, 0u);

  const PolygonFaces lonely = faces_of(11, {{8, 9, 10}});
  s = interior_stencils(lonely, 8, {});
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].w, kInvalid) << "9 and 10 come after 8";
  EXPECT_EQ(s[1].w, 8u);
  // Around 10: b = 9, a = 8, open. w = 9 (position 9 < 10), across it 8.
  EXPECT_EQ(s[2].w, 9u);
  EXPECT_EQ(s[2].far, 8u);
}

// A round trip through the codec of the pole, quantized and lossless: the decoder builds the same
// stencils from the faces it rebuilt.
TEST(InteriorStencils, APoleRoundTrips) {
  PolygonMesh m;
  // A 4x4 grid of quads with its middle 2x2 cells replaced by a fan of eight triangles around a pole.
  for (int y = 0; y <= 4; ++y)
    for (int x = 0; x <= 4; ++x)
      m.positions.insert(m.positions.end(), {float(x), float(y), 0.25f * float((x - 2) * (y - 2))});
  m.positions.insert(m.positions.end(), {2.0f, 2.0f, 0.5f});  // vertex 25, the pole
  const auto id = [](int x, int y) { return static_cast<std::uint32_t>(y * 5 + x); };
  m.face_offsets = {0};
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      if (x >= 1 && x <= 2 && y >= 1 && y <= 2) continue;
      m.corners.insert(m.corners.end(), {id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)});
      m.face_offsets.push_back(static_cast<std::uint32_t>(m.corners.size()));
    }
  const std::uint32_t ring[8] = {id(1, 1), id(2, 1), id(3, 1), id(3, 2),
                                 id(3, 3), id(2, 3), id(1, 3), id(1, 2)};
  for (int i = 0; i < 8; ++i) {
    m.corners.insert(m.corners.end(), {ring[i], ring[(i + 1) % 8], 25});
    m.face_offsets.push_back(static_cast<std::uint32_t>(m.corners.size()));
  }
  for (std::uint32_t bits : {0u, 14u}) {
    EncodeOptions o;
    o.keep_order = true;
    o.quantize_bits = bits;
    const std::string bytes = encode_polygons(m, o);
    EXPECT_EQ(bytes[9], kFormatMinorInterior);
    EXPECT_EQ(inspect(bytes).interior_positions, 1u);
    const PolygonMesh back = decode_polygons(bytes);
    EXPECT_EQ(back.corners, m.corners);
    ASSERT_EQ(back.positions.size(), m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i)
      EXPECT_NEAR(back.positions[i], m.positions[i], bits ? 4.0 / (1 << 14) : 0.0) << i;
  }
}

}  // namespace
}  // namespace qsp
