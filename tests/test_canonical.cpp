// Canonical labelling: invariance under renumbering, decodability of the code, symmetric meshes.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "layout_grid.h"
#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "stencil.h"
#include "support/corpus.h"
#include "support/mesh_gen.h"

namespace qsp {
namespace {

CanonicalMesh canon(const QuadMesh& m) {
  const Adjacency adj = build_adjacency(m);
  return canonicalize(m, adj, partition_motorcycle(adj));
}

// Positions in canonical layout order, all components, as raw bits.
std::vector<std::uint32_t> canonical_bits(const QuadMesh& m, const CanonicalMesh& c) {
  std::vector<std::uint32_t> out;
  for (const auto& comp : c.components)
    for (std::uint32_t v : comp.map.vertex)
      for (int k = 0; k < 3; ++k) {
        std::uint32_t b;
        std::memcpy(&b, &m.positions[3 * std::size_t(v) + k], 4);
        out.push_back(b);
      }
  return out;
}

// The layout rebuilt from the code alone is the input mesh, face for face, corner for corner.
void check_component(const QuadMesh& m, const CanonicalComponent& comp) {
  const ComponentPartition decoded = partition_from_code(comp.code);
  const GridLayout layout = grid_layout(decoded);
  ASSERT_EQ(layout.vertex_count, comp.map.vertex.size());
  ASSERT_EQ(layout.quads.size(), 4 * comp.map.face.size());
  for (std::size_t f = 0; f < comp.map.face.size(); ++f)
    for (std::uint32_t k = 0; k < 4; ++k)
      ASSERT_EQ(comp.map.vertex[layout.quads[4 * f + k]],
                m.quads[4 * comp.map.face[f] + (k + comp.map.rotation[f]) % 4])
          << "face " << f;
  Numbering numbering;
  (void)grid_layout(decoded, numbering);
  const ComponentStencils stencils = component_stencils(decoded, layout, numbering, CodingOrder::kLayout);
  for (std::uint32_t v = 0; v < layout.vertex_count; ++v) {
    const auto& s = stencils.stencil[v];
    for (std::uint32_t n : s.vertex_fields()) ASSERT_TRUE(n == kInvalid || n < v) << "stencil of " << v;
  }
}

TEST(Canonical, CorpusCodesDecodeAndIgnoreNumbering) {
  int n = 0;
  for (const auto& path : testing::corpus()) {
    SCOPED_TRACE(path.string());
    QuadMesh m;
    if (!testing::read_valid(path, m)) continue;
    const CanonicalMesh a = canon(m);
    for (const auto& comp : a.components) check_component(m, comp);
    const QuadMesh s = testing::shuffled(m, 99);
    const CanonicalMesh b = canon(s);
    ASSERT_EQ(a.components.size(), b.components.size());
    for (std::size_t i = 0; i < a.components.size(); ++i) {
      EXPECT_TRUE(a.components[i].code == b.components[i].code) << "component " << i;
      EXPECT_EQ(a.components[i].automorphisms, b.components[i].automorphisms);
    }
    EXPECT_EQ(topology_fingerprint(a), topology_fingerprint(b));
    EXPECT_EQ(canonical_bits(m, a), canonical_bits(s, b));
    ++n;
  }
  EXPECT_EQ(n, testing::expected_valid_count(testing::corpus()));
}

TEST(Canonical, SymmetricShapesCountTheirRotations) {
  // A refined cube has the 24 rotations of the cube.
  for (int k : {1, 2, 4}) {
    const CanonicalMesh c = canon(testing::cube(k));
    ASSERT_EQ(c.components.size(), 1u);
    EXPECT_EQ(c.components[0].automorphisms, 24u) << k;
  }
  // A square grid: 4 rotations; an oblong one: 2.
  EXPECT_EQ(canon(testing::grid(5, 5)).components[0].automorphisms, 4u);
  EXPECT_EQ(canon(testing::grid(5, 3)).components[0].automorphisms, 2u);
}

// A fan's n tied roots are found from the automorphisms of two traversals and chosen among by walking
// each only as far as its positions differ (n traversals took minutes at n = 40,000): the same form,
// whatever the numbering, with one rotation per spoke; with every position equal, all n are finalists.
TEST(Canonical, FansCountEverySpokeAndIgnoreNumbering) {
  for (const bool flat : {false, true})
    for (const int n : {3, 40, 700}) {
      SCOPED_TRACE(std::to_string(n) + (flat ? " flat" : ""));
      QuadMesh m = testing::fan(n, flat);
      testing::append(m, testing::fan(n, flat), 5);  // a remembered shape when small
      const CanonicalMesh a = canon(m);
      ASSERT_EQ(a.components.size(), 2u);
      for (const auto& comp : a.components) {
        EXPECT_EQ(comp.automorphisms, static_cast<std::uint32_t>(n));
        check_component(m, comp);
      }
      for (const std::uint64_t seed : {1, 2, 3}) {
        const QuadMesh s = testing::shuffled(m, seed);
        const CanonicalMesh b = canon(s);
        ASSERT_EQ(b.components.size(), 2u);
        for (std::size_t i = 0; i < 2; ++i) EXPECT_TRUE(a.components[i].code == b.components[i].code);
        EXPECT_EQ(canonical_bits(m, a), canonical_bits(s, b)) << "seed " << seed;
      }
    }
}

TEST(Canonical, StructuredKinds) {
  const CanonicalMesh torus = canon(testing::periodic(8, 5, true, 0));
  ASSERT_EQ(torus.components.size(), 1u);
  EXPECT_EQ(torus.components[0].code.kind, ComponentKind::kTorus);
  EXPECT_EQ(torus.components[0].code.a * torus.components[0].code.b, 40u);
  const CanonicalMesh annulus = canon(testing::periodic(8, 5, false, 0));
  EXPECT_EQ(annulus.components[0].code.kind, ComponentKind::kAnnulus);
  EXPECT_EQ(annulus.components[0].code.a, 8u);
  EXPECT_EQ(annulus.components[0].code.b, 5u);
  const CanonicalMesh disk = canon(testing::grid(4, 6));
  EXPECT_EQ(disk.components[0].code.kind, ComponentKind::kDisk);
  // Twisted tori with different twists are different topologies; the same twist shuffled is the same.
  const auto t1 = canon(testing::periodic(9, 6, true, 1)), t2 = canon(testing::periodic(9, 6, true, 2));
  EXPECT_FALSE(t1.components[0].code == t2.components[0].code);
  EXPECT_TRUE(canon(testing::shuffled(testing::periodic(9, 6, true, 2), 3)).components[0].code ==
              t2.components[0].code);
}

TEST(Canonical, StructuredLayoutsMatchTheMesh) {
  for (auto [a, b, t, torus] :
       {std::tuple{8, 5, 0, true}, {9, 6, 2, true}, {7, 7, 3, true}, {8, 5, 0, false}, {5, 9, 0, false}}) {
    const QuadMesh m = testing::periodic(a, b, torus, t);
    const CanonicalMesh c = canon(m);
    for (const auto& comp : c.components) check_component(m, comp);
  }
}

TEST(Canonical, MirroredCopyDiffersUnlessSymmetric) {
  // An L with equal arms is mirror-symmetric (about its diagonal), so its mirror image is the same
  // topology; a scaled F pentomino is chiral.
  auto mirror = [](QuadMesh m) {
    for (std::size_t f = 0; f < m.face_count(); ++f) std::swap(m.quads[4 * f + 1], m.quads[4 * f + 3]);
    return m;
  };
  const QuadMesh ell = testing::polyomino({"##..", "##..", "####", "####"});
  EXPECT_EQ(topology_fingerprint(canon(ell)), topology_fingerprint(canon(mirror(ell))));
  const QuadMesh f = testing::polyomino({"..####", "..####", "####..", "####..", "..##..", "..##.."});
  EXPECT_NE(topology_fingerprint(canon(f)), topology_fingerprint(canon(mirror(f))));
  // The diagonal-symmetric right-hand-rule shape matches its mirror image.
  const QuadMesh rh = testing::polyomino(
      {"######..", "######..", "########", "########", "########", "########", "..######", "..######"});
  EXPECT_EQ(topology_fingerprint(canon(rh)), topology_fingerprint(canon(mirror(rh))));
}

// The threaded seam (CONTRIBUTING, "Threads"): components canonicalized on two threads give the form one
// thread gives, forced on small meshes of several components (some interchangeable, some structured).
// The same canonical form, component for component, linked to the mesh the same way.
void expect_same_form(const CanonicalMesh& one, const CanonicalMesh& other) {
  ASSERT_EQ(one.components.size(), other.components.size());
  for (std::size_t i = 0; i < one.components.size(); ++i) {
    const CanonicalComponent &a = one.components[i], &b = other.components[i];
    EXPECT_TRUE(a.code == b.code) << "component " << i;
    EXPECT_EQ(a.automorphisms, b.automorphisms);
    EXPECT_EQ(a.map.vertex, b.map.vertex);
    EXPECT_EQ(a.map.face, b.map.face);
    EXPECT_EQ(a.map.rotation, b.map.rotation);
    EXPECT_EQ(a.part.schematic.dart_halfedge, b.part.schematic.dart_halfedge);
    EXPECT_EQ(a.part.anchor_halfedge, b.part.anchor_halfedge);
  }
  EXPECT_EQ(one.unreferenced, other.unreferenced);
}

TEST(Canonical, TwoThreadsGiveTheSameForm) {
  std::vector<QuadMesh> meshes;
  meshes.push_back(testing::copies(testing::cube(2), 5, 3.0f));
  QuadMesh mixed = testing::grid(4, 6);
  testing::append(mixed, testing::periodic(8, 5, true, 0), 10.0f);
  testing::append(mixed, testing::periodic(8, 5, false, 0), 20.0f);
  testing::append(mixed, testing::cube(3), 30.0f);
  testing::append(mixed, testing::polyomino({"##..", "##..", "####", "####"}), 40.0f);
  meshes.push_back(testing::shuffled(mixed, 7));
  mixed.positions.insert(mixed.positions.end(), {1.0f, 2.0f, 3.0f, 0.5f, 0.5f, 0.5f});  // unreferenced
  meshes.push_back(mixed);
  // One large component: its patches walked on the second core, its map turned from those walks.
  meshes.push_back(testing::shuffled(testing::cube(40), 3));  // 9600 faces, patches turned every way
  for (const char* name : {"mh_base.obj", "mh_female_generic.obj"}) {
    const std::filesystem::path path = testing::shared_dir() / "meshes" / name;
    if (std::filesystem::exists(path)) meshes.push_back(read_mesh_file(path.string()));
  }
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    SCOPED_TRACE(k);
    const QuadMesh& m = meshes[k];
    const Adjacency adj = build_adjacency(m);
    const Partition p = partition_motorcycle(adj);
    const CanonicalMesh one = canonicalize(m, adj, p, 1);
    expect_same_form(one, canonicalize(m, adj, p, 2));
    expect_same_form(one, canonicalize(m, adj, p, 0));
  }
}

TEST(Canonical, HostileCodesAreRefused) {
  TopologyCode c;
  c.next_ref = {5, 0};
  c.edge_length = {1};
  c.corner = {0, 0};
  EXPECT_THROW(partition_from_code(c), Error);
  c.next_ref = {0, 0, 0, 0};
  c.edge_length = {1, 1};
  c.corner = {1, 1, 1, 1};
  EXPECT_THROW(partition_from_code(c), Error);
  c = {};
  c.kind = ComponentKind::kTorus;
  c.a = 0xFFFFFFFu;
  c.b = 0xFFFFFFFu;
  EXPECT_THROW(partition_from_code(c), Error);
}

}  // namespace
}  // namespace qsp
