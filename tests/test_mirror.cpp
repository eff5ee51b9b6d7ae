// Mirror prediction (format 3.17): the encoder's search finds a symmetric mesh's mirror, the propagation
// from its seed is that mirror (an involution reflecting the positions) and refuses seeds that are no
// automorphism, renumbered copies give the same bytes, and a hostile symmetry section is refused where
// it breaks a rule, never crashing the decoder.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "container.h"
#include "mirror.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "support/files.h"
#include "support/mesh_gen.h"
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
  const Mirror m = mirror_vertices(hull.quads, adj, seeds, "test");
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

}  // namespace
}  // namespace qsp
