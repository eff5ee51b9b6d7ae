// Matching and fingerprints of polygon meshes (qsp/match.h, qsp/fingerprint.h): renumbered copies of every
// hand-made and corpus polygon mesh match with a map checked here face by face and get the same
// fingerprint; a flipped diagonal between two triangles, which changes the multiset of vertex valences
// (so the meshes are surely not isomorphic), gives another fingerprint and "not isomorphic"; hand cases
// name the level that differs.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "qsp/error.h"
#include "qsp/fingerprint.h"
#include "qsp/match.h"
#include "qsp/submesh.h"
#include "support/corpus.h"
#include "support/mesh_gen.h"
#include "support/polygon.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::Grid;
using testing::Poly;

// Distinct positions on a line where a case has none, so the cost is meaningful.
PolygonMesh to_mesh(const Poly& p) { return testing::to_mesh(p, 1.0f); }

// A renumbered copy: vertex v becomes vperm[v], face f goes to place fperm[f] with its corners rotated by
// rot[f]; positions follow their vertices.
struct Shuffled {
  PolygonMesh mesh;
  std::vector<std::uint32_t> vperm, fperm, rot;
};

Shuffled shuffle(const PolygonMesh& m, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const auto nv = static_cast<std::uint32_t>(m.vertex_count()),
             nf = static_cast<std::uint32_t>(m.face_count());
  Shuffled s;
  s.vperm.resize(nv);
  std::iota(s.vperm.begin(), s.vperm.end(), 0u);
  std::shuffle(s.vperm.begin(), s.vperm.end(), rng);
  std::vector<std::uint32_t> order(nf);
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), rng);
  s.fperm.resize(nf);
  s.rot.resize(nf);
  s.mesh.positions.resize(m.positions.size());
  for (std::uint32_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) s.mesh.positions[3 * s.vperm[v] + k] = m.positions[3 * v + k];
  for (std::uint32_t place = 0; place < nf; ++place) {
    const std::uint32_t f = order[place], d = m.degree(f), r = rng() % d;
    s.fperm[f] = place;
    s.rot[f] = r;
    for (std::uint32_t i = 0; i < d; ++i)
      s.mesh.corners.push_back(s.vperm[m.corners[m.face_offsets[f] + (i + r) % d]]);
    s.mesh.face_offsets.push_back(static_cast<std::uint32_t>(s.mesh.corners.size()));
  }
  return s;
}

// The test's own check, independent of verify_polygon_match: the vertex map is a bijection and every
// face of A is, under it, a face of B of the same degree with the same cyclic corner order, each face of
// B used once.
void expect_face_by_face(const PolygonMesh& a, const PolygonMesh& b, const PolygonMatchResult& r) {
  ASSERT_TRUE(r.isomorphic) << r.reason;
  ASSERT_EQ(r.vertex.size(), a.vertex_count());
  ASSERT_EQ(r.face.size(), a.face_count());
  std::set<std::uint32_t> images(r.vertex.begin(), r.vertex.end());
  ASSERT_EQ(images.size(), a.vertex_count());
  ASSERT_TRUE(images.empty() || *images.rbegin() < b.vertex_count());
  std::vector<int> used(b.face_count(), 0);
  for (std::size_t f = 0; f < a.face_count(); ++f) {
    const std::uint32_t g = r.face[f], d = a.degree(f);
    ASSERT_LT(g, b.face_count());
    ASSERT_EQ(used[g]++, 0) << "face " << g << " of B is the image of two faces";
    ASSERT_EQ(b.degree(g), d) << "face " << f;
    for (std::uint32_t c = 0; c < d; ++c) {
      const std::uint32_t k = r.mirrored ? (r.rotation[f] + d - c) % d : (c + r.rotation[f]) % d;
      ASSERT_EQ(r.vertex[a.corners[a.face_offsets[f] + c]], b.corners[b.face_offsets[g] + k])
          << "face " << f << " corner " << c;
    }
  }
}

// support/polygon.h's flip_a_diagonal on the mesh's arrays (positions follow).
bool flip_a_diagonal(const PolygonMesh& m, PolygonMesh& out) {
  const Poly p{m.face_offsets, m.corners, static_cast<std::uint32_t>(m.vertex_count()), m.positions};
  Poly flipped;
  if (!testing::flip_a_diagonal(p, flipped)) return false;
  out = to_mesh(flipped);
  return true;
}

// Renumbered copies match face by face and share the fingerprint; a rigid mesh's map is the renumbering
// itself. Returns whether the mesh could be checked (false: not a mesh, as the manifest says).
void expect_matches_its_copies(const PolygonMesh& m, const std::string& name) {
  SCOPED_TRACE(name);
  const PolygonMatchInput a = prepare_polygon_match(m);
  const std::uint64_t fp = polygon_fingerprint(a);
  for (std::uint32_t seed : {1u, 2u}) {
    const Shuffled s = shuffle(m, seed);
    const PolygonMatchInput b = prepare_polygon_match(s.mesh);
    EXPECT_EQ(polygon_fingerprint(b), fp) << "seed " << seed;
    if (a.capped) continue;  // the one case the codes may depend on the numbering
    const PolygonMatchResult r = match_polygons(a, b);
    expect_face_by_face(m, s.mesh, r);
    EXPECT_TRUE(verify_polygon_match(m, s.mesh, r));
    EXPECT_TRUE(r.same_positions) << "a copy with the same positions is matched keeping them";
    if (r.unique) {
      std::vector<std::uint8_t> used(m.vertex_count(), 0);
      for (std::uint32_t v : m.corners) used[v] = 1;
      for (std::uint32_t v = 0; v < m.vertex_count(); ++v)
        if (used[v]) {
          EXPECT_EQ(r.vertex[v], s.vperm[v]) << "vertex " << v;
        }
    }
  }
}

void expect_flip_differs(const PolygonMesh& m, const std::string& name, int& flipped) {
  SCOPED_TRACE(name);
  PolygonMesh f;
  if (!flip_a_diagonal(m, f)) return;
  const PolygonMatchInput a = prepare_polygon_match(m), b = prepare_polygon_match(shuffle(f, 9).mesh);
  EXPECT_NE(polygon_fingerprint(a), polygon_fingerprint(b));
  if (a.capped || b.capped) return;
  const PolygonMatchResult r = match_polygons(a, b);
  EXPECT_FALSE(r.isomorphic);
  EXPECT_NE(r.level, MatchLevel::kNone);
  EXPECT_FALSE(r.reason.empty());
  ++flipped;
}

TEST(MatchPolygons, HandMadeCasesMatchRenumberedCopiesFaceByFace) {
  for (const auto& [name, p] : testing::hand_polygon_cases()) expect_matches_its_copies(to_mesh(p), name);
}

TEST(MatchPolygons, HandMadeFlippedDiagonalsAreNotIsomorphic) {
  int flipped = 0;
  for (const auto& [name, p] : testing::hand_polygon_cases()) expect_flip_differs(to_mesh(p), name, flipped);
  EXPECT_GE(flipped, 5);
}

bool all_quad_manifold(const PolygonMesh& m) {
  for (std::size_t f = 0; f < m.face_count(); ++f)
    if (m.degree(f) != 4) return false;
  QuadMesh q;
  q.positions = m.positions;
  q.quads = m.corners;
  try {
    (void)build_adjacency(q);
    return true;
  } catch (const Error&) {
    return false;
  }
}

// Every non-quad (or non-manifold) mesh of ../shared/meshes and osd_shapes/.
TEST(MatchPolygons, SharedPolygonMeshesMatchCopiesAndNotFlips) {
  QSP_NEEDS_SHARED();
  int meshes = 0, flipped = 0;
  for (const fs::path& path : testing::shared_meshes()) {
    const Poly p = testing::read_faces(path);
    const PolygonMesh m = to_mesh(p);
    if (m.face_count() > 40000 || all_quad_manifold(m) || !testing::cuttable(p)) continue;
    expect_matches_its_copies(m, path.filename().string());
    expect_flip_differs(m, path.filename().string(), flipped);
    ++meshes;
  }
  EXPECT_GE(meshes, 20);
  EXPECT_GE(flipped, 8);
}

// An all-quad manifold mesh keeps the fingerprint it has always had.
TEST(MatchPolygons, QuadMeshesKeepTheirFingerprint) {
  for (const QuadMesh& q : {testing::grid(4, 3), testing::cube(3), testing::periodic(5, 4, true, 0)}) {
    EXPECT_EQ(polygon_fingerprint(prepare_polygon_match(polygon_mesh(q))), mesh_fingerprint(q));
  }
}

// A triangle fan of four triangles around a centre against the quad it fills: the face degrees differ.
TEST(MatchPolygons, TriangleFanAgainstAQuadDiffersInFaceDegrees) {
  Poly quad;
  quad.nv = 5;
  quad.face({0, 1, 2, 3});
  Poly fan;
  fan.nv = 5;
  for (std::uint32_t i = 0; i < 4; ++i) fan.face({i, (i + 1) % 4, 4});
  const PolygonMatchInput a = prepare_polygon_match(to_mesh(quad)), b = prepare_polygon_match(to_mesh(fan));
  EXPECT_NE(polygon_fingerprint(a), polygon_fingerprint(b));
  const PolygonMatchResult r = match_polygons(a, b);
  EXPECT_FALSE(r.isomorphic);
  EXPECT_EQ(r.level, MatchLevel::kFaceDegrees);
  EXPECT_EQ(r.reason, "face degrees: A has 0 triangles, B has 4 triangles") << r.reason;
}

// Two meshes differing only by where one quad of a grid is split into two triangles: same face degrees,
// same quad count, but a corner cell against a middle one.
TEST(MatchPolygons, OneTriangleSplitElsewhereIsNotIsomorphic) {
  const Poly corner = Grid::make(3, 3, [](int i, int j) { return i == 0 && j == 0 ? 't' : 'q'; }).p;
  const Poly middle = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? 't' : 'q'; }).p;
  const Poly edge = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 0 ? 't' : 'q'; }).p;
  const PolygonMatchInput a = prepare_polygon_match(to_mesh(corner)),
                          b = prepare_polygon_match(to_mesh(middle)),
                          c = prepare_polygon_match(to_mesh(edge));
  EXPECT_NE(polygon_fingerprint(a), polygon_fingerprint(b));
  EXPECT_NE(polygon_fingerprint(a), polygon_fingerprint(c));
  EXPECT_NE(polygon_fingerprint(b), polygon_fingerprint(c));
  for (const auto* other : {&b, &c}) {
    const PolygonMatchResult r = match_polygons(a, *other);
    EXPECT_FALSE(r.isomorphic);
    EXPECT_NE(r.level, MatchLevel::kFaceDegrees) << r.reason;  // the degrees agree
  }
  // The split cell turned by a quarter (the other diagonal) in the middle of a symmetric grid is the same
  // mesh turned: isomorphic, and the map is checked face by face.
  Grid turned = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? '.' : 'q'; });
  turned.p.face({turned.id(1, 1), turned.id(2, 1), turned.id(2, 2)});
  turned.p.face({turned.id(1, 1), turned.id(2, 2), turned.id(1, 2)});
  const PolygonMesh mt = to_mesh(turned.p), mm = to_mesh(middle);
  const PolygonMatchResult r = match_polygons(prepare_polygon_match(mm), prepare_polygon_match(mt));
  expect_face_by_face(mm, mt, r);
  EXPECT_FALSE(r.unique);  // a symmetric mesh: one isomorphism of several
}

// The diagonal of a quad-shaped triangle pair in a corner cell flipped: the region's codes differ.
TEST(MatchPolygons, FlippedDiagonalIsReportedAtTheRegions) {
  const Poly a = Grid::make(4, 3, [](int i, int j) { return i == 0 && j == 0 ? 't' : 'q'; }).p;
  Grid g = Grid::make(4, 3, [](int i, int j) { return i == 0 && j == 0 ? '.' : 'q'; });
  g.p.face({g.id(0, 0), g.id(1, 0), g.id(1, 1)});
  g.p.face({g.id(0, 0), g.id(1, 1), g.id(0, 1)});
  const PolygonMatchResult r =
      match_polygons(prepare_polygon_match(to_mesh(a)), prepare_polygon_match(to_mesh(g.p)));
  EXPECT_FALSE(r.isomorphic);
  EXPECT_EQ(r.level, MatchLevel::kRegions) << r.reason;
  EXPECT_EQ(r.reason.rfind("non-quad regions: ", 0), 0u) << r.reason;
}

// Mirrors: a chiral polygon mesh against its reversed copy matches only with Mirror::kAccept (the map
// reverses corners), and kHint says that it would.
TEST(MatchPolygons, MirrorsAreHintedOrAcceptedAsForQuads) {
  const Poly p =
      Grid::make(4, 3, [](int i, int j) { return (i == 0 && j == 0) || (i == 2 && j == 0) ? 't' : 'q'; }).p;
  PolygonMesh a = to_mesh(p), b = a;
  for (std::size_t f = 0; f < b.face_count(); ++f)
    std::reverse(b.corners.begin() + b.face_offsets[f] + 1, b.corners.begin() + b.face_offsets[f + 1]);
  const PolygonMatchInput pa = prepare_polygon_match(a), pb = prepare_polygon_match(b);
  MatchOptions o;
  const PolygonMatchResult plain = match_polygons(pa, pb, o);
  if (plain.isomorphic) GTEST_SKIP() << "this case turned out mirror-symmetric";
  o.mirror = Mirror::kHint;
  EXPECT_TRUE(match_polygons(pa, pb, o).mirror_would_match);
  o.mirror = Mirror::kAccept;
  const PolygonMatchResult r = match_polygons(pa, pb, o);
  EXPECT_TRUE(r.mirrored);
  expect_face_by_face(a, b, r);
}

// prefer_order: the identity of indices where it is an isomorphism, even on a symmetric mesh.
TEST(MatchPolygons, PreferOrderKeepsTheIdentity) {
  const PolygonMesh m =
      to_mesh(Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? 't' : 'q'; }).p);
  PolygonMesh moved = m;  // same order, other positions: a morph
  for (float& x : moved.positions) x *= 2;
  MatchOptions o;
  o.prefer_order = true;
  const PolygonMatchResult r = match_polygons(prepare_polygon_match(m), prepare_polygon_match(moved), o);
  expect_face_by_face(m, moved, r);
  EXPECT_TRUE(r.identity);
  for (std::uint32_t v = 0; v < r.vertex.size(); ++v) EXPECT_EQ(r.vertex[v], v);
}

TEST(MatchPolygons, NotAMeshIsRefused) {
  PolygonMesh m;
  m.positions.assign(12, 0.0f);
  m.corners = {0, 1, 1};
  m.face_offsets = {0, 3};
  EXPECT_THROW(prepare_polygon_match(m), Error);
  m.corners = {0, 1, 7};
  EXPECT_THROW(prepare_polygon_match(m), Error);
  m.face_offsets = {0, 5};
  EXPECT_THROW(prepare_polygon_match(m), Error);
}

// A regular triangulated torus (every vertex of valence 6, all alike): its one region has no quad and
// 6n^2 tied starts, more than canonical_regions compares. It is flagged, and a renumbered copy is
// either matched (map checked face by face) or refused as undecidable: never "not isomorphic".
TEST(MatchPolygons, TooSymmetricTriangleMeshesAreNeverCalledDifferent) {
  const std::uint32_t n = 6;
  Poly p;
  p.nv = n * n;
  auto v = [&](std::uint32_t i, std::uint32_t j) { return (j % n) * n + i % n; };
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      p.face({v(i, j), v(i + 1, j), v(i, j + 1)});
      p.face({v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  const PolygonMesh m = to_mesh(p);
  const PolygonMatchInput a = prepare_polygon_match(m);
  EXPECT_TRUE(a.capped);
  EXPECT_FALSE(a.rigid);
  int matched = 0, refused = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const Shuffled s = shuffle(m, seed);
    try {
      const PolygonMatchResult r = match_polygons(a, prepare_polygon_match(s.mesh));
      expect_face_by_face(m, s.mesh, r);
      ++matched;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kUnsupported) << e.what();
      EXPECT_NE(std::string(e.what()).find("cannot decide"), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_EQ(matched + refused, 6);
}

// Symmetric hand cases moved a little (and renumbered): each vertex goes to the vertex it was, not to a
// symmetric one, because B's vertices are told apart by their nearest A vertices (`snapped`).
TEST(MatchPolygons, SymmetricMeshesMovedALittleMatchTheirOwnVertices) {
  int snapped = 0;
  for (const auto& [name, p] : testing::hand_polygon_cases()) {
    SCOPED_TRACE(name);
    const PolygonMesh m = to_mesh(p);  // vertex v at (v, 0, 0): symmetric vertices lie far apart
    Shuffled s = shuffle(m, 4);
    std::mt19937 rng(8);
    for (float& x : s.mesh.positions) x += std::uniform_real_distribution<float>(-0.05f, 0.05f)(rng);
    const PolygonMatchInput a = prepare_polygon_match(m);
    if (a.capped) continue;
    const PolygonMatchResult r = match_polygons(a, prepare_polygon_match(s.mesh));
    expect_face_by_face(m, s.mesh, r);
    std::vector<std::uint8_t> used(m.vertex_count(), 0);
    for (std::uint32_t v : m.corners) used[v] = 1;
    for (std::uint32_t v = 0; v < m.vertex_count(); ++v)
      if (used[v]) {
        EXPECT_EQ(r.vertex[v], s.vperm[v]) << "vertex " << v;
      }
    snapped += r.snapped;
  }
  EXPECT_GE(snapped, 5);
}

}  // namespace
}  // namespace qsp
