// Mirror prediction (format 3.17): the encoder's search finds a symmetric mesh's mirror, the propagation
// from its seed is that mirror (an involution reflecting the positions) and refuses seeds that are no
// automorphism, renumbered copies give the same bytes, and a hostile symmetry section is refused where
// it breaks a rule, never crashing the decoder. Texture coordinates predicted from their mirror images'
// (3.18) come back exactly, in order with --keep-order, and survive every flip of their section.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "codec_encode.h"
#include "container.h"
#include "mirror.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/mesh_gen.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

const std::string kMirror = std::string(QSP_TESTDATA_DIR) + "/golden/mirror/";

TEST(Mirror, TheHullsMirrorReflectsItAcrossX) {
  const QuadMesh hull = read_mesh_file(kMirror + "hull.obj");
  const Adjacency adj = build_adjacency(hull);
  const std::vector<MirrorSeed> seeds = find_mirror(hull.quads, adj, hull.positions);
  ASSERT_EQ(seeds.size(), 1u);
  EXPECT_EQ(seeds[0].axis, 0u);
  const MirrorMap m = mirror_vertices(hull.quads, adj, seeds, "test");
  for (std::uint32_t v = 0; v < hull.vertex_count(); ++v) {
    const std::uint32_t w = m.image[v];
    ASSERT_LT(w, hull.vertex_count()) << v;
    EXPECT_EQ(m.image[w], v) << "an involution";
    EXPECT_EQ(m.axis[v], 0);
    EXPECT_EQ(hull.positions[3 * w], -hull.positions[3 * v]) << v;
    EXPECT_EQ(hull.positions[3 * w + 1], hull.positions[3 * v + 1]) << v;
    EXPECT_EQ(hull.positions[3 * w + 2], hull.positions[3 * v + 2]) << v;
  }
}

TEST(Mirror, SeedsThatAreNoMirrorAreRefused) {
  const QuadMesh hull = read_mesh_file(kMirror + "hull.obj");
  const Adjacency adj = build_adjacency(hull);
  // Face 0 onto itself reversed, every turn: a corner face's reflection in its own diagonal maps a
  // boundary edge onto an inner one, or the grid onto no grid.
  for (std::uint32_t turn = 0; turn < 4; ++turn) {
    const MirrorSeed seed{0, 0, turn, 0};
    EXPECT_THROW((void)mirror_vertices(hull.quads, adj, std::span(&seed, 1), "test"), Error) << turn;
  }
  const MirrorSeed past{static_cast<std::uint32_t>(hull.face_count()), 0, 0, 0};
  EXPECT_THROW((void)mirror_vertices(hull.quads, adj, std::span(&past, 1), "test"), Error);
  // No seed where no reflection across an axis is a mirror: an L of quads (its mirror is diagonal).
  const QuadMesh l = read_mesh_file(std::string(QSP_TESTDATA_DIR) + "/golden/l_shape.obj");
  EXPECT_TRUE(find_mirror(l.quads, build_adjacency(l), l.positions).empty());
}

// The mirror search's adjacency, the input's renumbered as the layout numbers it, is what building the
// layout's quads gives on every field the search and propagation read, and on the rest but which
// outgoing half-edge a vertex names and how exterior half-edges are numbered: over the corpus.
TEST(Mirror, TheLayoutsAdjacencyIsTheInputsRenumbered) {
  int checked = 0;
  for (const auto& path : testing::corpus()) {
    QuadMesh mesh;
    Adjacency adj;
    if (!testing::read_valid(path, mesh, &adj) || mesh.vertex_count() > 40000) continue;
    SCOPED_TRACE(path.string());
    EncodeOptions o;
    o.level = 1;
    OrderMap order;
    (void)encode_tuned(mesh, o, {}, &order);
    const std::uint32_t nf = adj.face_count, nv = adj.vertex_count;
    std::vector<std::uint32_t> quads(4 * std::size_t{nf});
    for (std::uint32_t f = 0; f < nf; ++f)
      for (std::uint32_t c = 0; c < 4; ++c)
        quads[4 * std::size_t{order.face[f]} + c] =
            order.vertex[mesh.quads[4 * f + ((c + order.rotation[f]) & 3u)]];
    const Adjacency built = build_adjacency(quads, nv);
    const Adjacency renumbered = layout_adjacency(adj, order);
    ASSERT_EQ(renumbered.twin.size(), built.twin.size());
    for (std::uint32_t h = 0; h < 4 * nf; ++h) {
      ASSERT_EQ(renumbered.is_exterior(renumbered.twin[h]), built.is_exterior(built.twin[h])) << h;
      if (!built.is_exterior(built.twin[h])) {
        ASSERT_EQ(renumbered.twin[h], built.twin[h]) << h;
      }
      ASSERT_EQ(renumbered.origin[h], built.origin[h]) << h;
    }
    for (std::uint32_t h = 0; h < renumbered.twin.size(); ++h) {
      ASSERT_EQ(renumbered.twin[renumbered.twin[h]], h);
      ASSERT_EQ(renumbered.origin[renumbered.twin[h]], renumbered.dest(h));
    }
    EXPECT_EQ(renumbered.valence, built.valence);
    EXPECT_EQ(renumbered.boundary, built.boundary);
    EXPECT_EQ(renumbered.face_component, built.face_component);
    EXPECT_EQ(renumbered.component_faces, built.component_faces);
    EXPECT_EQ(renumbered.component_count, built.component_count);
    for (std::uint32_t v = 0; v < nv; ++v)
      if (renumbered.vertex_halfedge[v] != kInvalid) {
        EXPECT_EQ(renumbered.origin[renumbered.vertex_halfedge[v]], v);
      }
    ++checked;
  }
  EXPECT_GE(checked, 20);
}

// The mirror the search keeps from its own propagations is the one its seeds determine, over the corpus
// (the symmetric meshes among it: MakeHuman's, Spot, Blub, the hull).
TEST(Mirror, TheSearchsMirrorIsItsSeedsPropagated) {
  int mirrored = 0;
  for (const auto& path : testing::corpus()) {
    QuadMesh mesh;
    Adjacency adj;
    if (!testing::read_valid(path, mesh, &adj) || mesh.vertex_count() > 40000) continue;
    SCOPED_TRACE(path.string());
    MirrorMap found;
    const std::vector<MirrorSeed> seeds = find_mirror(mesh.quads, adj, mesh.positions, &found);
    const MirrorMap m = mirror_vertices(mesh.quads, adj, seeds, "test");
    EXPECT_EQ(found.image, m.image);
    EXPECT_EQ(found.axis, m.axis);
    mirrored += !seeds.empty();
  }
  EXPECT_GE(mirrored, 3);
}

TEST(Mirror, RenumberedCopiesGiveTheSameBytes) {
  const QuadMesh three = read_mesh_file(kMirror + "three_parts_q14.obj");
  for (const int level : {1, kDefaultLevel, kMaxLevel}) {
    for (const std::uint32_t bits : {0u, 14u}) {
      EncodeOptions o;
      o.level = level;
      o.quantize_bits = bits;
      const std::string bytes = encode(three, o);
      EXPECT_NE(container::parse(bytes).find(container::kTagSymmetry), nullptr) << level << " " << bits;
      for (const std::uint64_t seed : {1, 2}) EXPECT_EQ(encode(testing::shuffled(three, seed), o), bytes);
    }
  }
}

TEST(Mirror, EveryBitFlipAndCutOfTheSymmetrySectionIsSafe) {
  const std::string good = testing::slurp(kMirror + "hull_q14.qsp");
  const std::size_t vertices = read_mesh_file(kMirror + "hull_q14.obj").vertex_count();
  testing::sweep_section(good, container::kTagSymmetry, kFormatMinorMirror, [&](const PolygonMesh& got) {
    EXPECT_EQ(got.vertex_count(), vertices);
    for (const float x : got.positions) EXPECT_TRUE(std::isfinite(x));
  });
}

// Each face as the cycle of its corners' position and texture coordinate bits, from its smallest corner,
// the faces sorted: the mesh up to its numbering.
std::vector<std::vector<std::array<std::uint32_t, 5>>> corner_cycles(const PolygonMesh& m) {
  std::vector<std::vector<std::array<std::uint32_t, 5>>> out;
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    std::vector<std::array<std::uint32_t, 5>> face;
    for (std::uint32_t k = m.face_offsets[f]; k < m.face_offsets[f + 1]; ++k) {
      std::array<std::uint32_t, 5> c{};
      std::memcpy(c.data(), &m.positions[3 * std::size_t{m.corners[k]}], 12);
      std::memcpy(c.data() + 3, &m.texcoords[2 * std::size_t{m.corner_texcoords[k]}], 8);
      face.push_back(c);
    }
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
    out.push_back(face);
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Mirror, TexcoordsFromTheirMirrorImagesComeBackExactly) {
  for (const std::string& path :
       {kMirror + "hull_uv12.obj", std::string(QSP_TESTDATA_DIR) + "/mh_fedora.obj"}) {
    SCOPED_TRACE(path);
    const PolygonMesh mesh = testing::read_obj_polygons(path);
    ASSERT_EQ(mesh.texcoord_components, 2);
    PolygonMesh rounded = mesh;  // on the grid of step 2^-12, as the spec rounds them
    for (float& x : rounded.texcoords)
      x = static_cast<float>(std::ldexp(std::nearbyint(std::ldexp(static_cast<double>(x), 12)), -12)) + 0.0f;
    for (const bool keep : {false, true}) {
      EncodeOptions o;
      o.level = kMaxLevel;
      o.quantize_texcoord_bits = 12;
      o.keep_order = keep;
      const std::string bytes = encode_polygons(mesh, o);
      const container::File file = container::parse(bytes);
      ASSERT_NE(file.find(container::kTagTexcoords), nullptr);
      EXPECT_TRUE(file.find(container::kTagTexcoords)->payload[0] & 0x20) << "predicted from the mirror";
      EXPECT_EQ(file.minor, kFormatMinorTexcoordMirror);
      const PolygonMesh back = decode_polygons(bytes);
      if (keep) {
        EXPECT_EQ(back.corners, mesh.corners);
        EXPECT_EQ(back.corner_texcoords, mesh.corner_texcoords);
        EXPECT_EQ(back.texcoords, rounded.texcoords);
      } else {
        EXPECT_EQ(corner_cycles(back), corner_cycles(rounded));
      }
      // Renumbered, the same bytes (canonical order: the mirror and its signs follow the layout).
      if (!keep) {
        EXPECT_EQ(encode_polygons(testing::renumbered(mesh, 7), o), bytes);
      }
    }
  }
}

TEST(Mirror, EveryBitFlipAndCutOfMirroredTexcoordsIsSafe) {
  const std::string good = testing::slurp(kMirror + "hull_uv12.qsp");
  const PolygonMesh mesh = testing::read_obj_polygons(kMirror + "hull_uv12.obj");
  const int decoded = testing::sweep_section(good, container::kTagTexcoords, kFormatMinorTexcoordMirror,
                                             [&](const PolygonMesh& got) {
                                               EXPECT_EQ(got.corners.size(), mesh.corners.size());
                                               EXPECT_EQ(got.corner_texcoords.size(), mesh.corners.size());
                                               for (const float x : got.texcoords)
                                                 EXPECT_TRUE(std::isfinite(x));
                                             });
  EXPECT_GT(decoded, 0);
}

}  // namespace
}  // namespace qsp
