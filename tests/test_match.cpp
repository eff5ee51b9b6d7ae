// Mesh matching: shuffled and morphed copies, mirrors, near-misses, symmetric meshes, the CLI.
// Claims of (non-)isomorphism and symmetry counts on small meshes are checked against a brute-force
// half-edge search that shares no code with the canonical partition.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <sstream>

#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/match.h"
#include "qsp/partition.h"
#include "support/cli.h"
#include "support/corpus.h"
#include "support/mesh_gen.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

// ---- Independent reference: brute-force isomorphisms of connected meshes ----

// Number of orientation-preserving isomorphisms a -> b (both connected, no unreferenced vertices):
// map A's half-edge 0 to every interior half-edge of B and propagate along next and twin.
std::uint64_t brute_force_isomorphisms(const QuadMesh& a, const QuadMesh& b) {
  const Adjacency x = build_adjacency(a), y = build_adjacency(b);
  if (x.halfedge_count() != y.halfedge_count() || x.face_count != y.face_count) return 0;
  const std::uint32_t nh = x.halfedge_count();
  std::uint64_t count = 0;
  std::vector<std::uint32_t> fwd(nh), back(nh), stack;
  for (std::uint32_t g0 = 0; g0 < 4 * y.face_count; ++g0) {
    std::fill(fwd.begin(), fwd.end(), kInvalid);
    std::fill(back.begin(), back.end(), kInvalid);
    bool ok = true;
    auto put = [&](std::uint32_t h, std::uint32_t g) {
      if (fwd[h] == g) return;
      if (fwd[h] != kInvalid || back[g] != kInvalid || x.is_exterior(h) != y.is_exterior(g)) {
        ok = false;
        return;
      }
      fwd[h] = g;
      back[g] = h;
      stack.push_back(h);
    };
    stack.clear();
    put(0, g0);
    while (ok && !stack.empty()) {
      const std::uint32_t h = stack.back();
      stack.pop_back();
      put(x.next(h), y.next(fwd[h]));
      put(x.twin[h], y.twin[fwd[h]]);
    }
    if (ok && std::count(fwd.begin(), fwd.end(), kInvalid) == 0) ++count;
  }
  return count;
}

// ---- Meshes ----

// Surface of the box [0,ex]x[0,ey]x[0,ez] in unit quads, outward counter-clockwise.
QuadMesh box(int ex, int ey, int ez) {
  testing::MeshBuilder b;
  const int ext[3] = {ex, ey, ez};
  // origin flags (1 = at the far side), u axis, v axis; u x v points outward.
  const int sides[6][5] = {{0, 0, 1, 0, 1}, {0, 0, 0, 1, 0}, {1, 0, 0, 1, 2},
                           {0, 0, 0, 2, 1}, {0, 1, 0, 2, 0}, {0, 0, 0, 0, 2}};
  for (const auto& s : sides)
    for (int j = 0; j < ext[s[4]]; ++j)
      for (int i = 0; i < ext[s[3]]; ++i) {
        auto P = [&](int p, int q) {
          std::array<int, 3> c{s[0] * ext[0], s[1] * ext[1], s[2] * ext[2]};
          c[s[3]] += p;
          c[s[4]] += q;
          return c;
        };
        b.quad({P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)});
      }
  return b.take();
}

// cube(n) cut along the horizontal loop z = k and reglued with the upper part turned by `shift`
// positions along the loop: same counts and valences; a cube again exactly when shift % n == 0.
QuadMesh sheared_cube(int n, int k, int shift) {
  QuadMesh m = testing::cube(n);
  std::vector<std::uint32_t> loop;
  for (std::uint32_t v = 0; v < m.vertex_count(); ++v)
    if (m.positions[3 * v + 2] == float(k)) loop.push_back(v);
  auto angle = [&](std::uint32_t v) {
    return std::atan2(m.positions[3 * v + 1] - n / 2.0, m.positions[3 * v] - n / 2.0);
  };
  std::sort(loop.begin(), loop.end(), [&](auto p, auto q) { return angle(p) < angle(q); });
  std::map<std::uint32_t, std::uint32_t> moved;
  for (std::size_t i = 0; i < loop.size(); ++i) moved[loop[i]] = loop[(i + shift) % loop.size()];
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    bool upper = true;
    for (int c = 0; c < 4; ++c) upper &= m.positions[3 * m.quads[4 * f + c] + 2] >= float(k);
    if (!upper) continue;
    for (int c = 0; c < 4; ++c)
      if (auto it = moved.find(m.quads[4 * f + c]); it != moved.end()) m.quads[4 * f + c] = it->second;
  }
  return m;
}

// Mirror image: x negated, every face's orientation reversed.
QuadMesh mirrored(QuadMesh m) {
  for (std::size_t v = 0; v < m.vertex_count(); ++v) m.positions[3 * v] = -m.positions[3 * v];
  for (std::size_t f = 0; f < m.face_count(); ++f) std::swap(m.quads[4 * f + 1], m.quads[4 * f + 3]);
  return m;
}

// Positions transformed by p -> R p + t (R integer 3x3, row-major).
QuadMesh transformed(QuadMesh m, const std::array<int, 9>& r, std::array<float, 3> t = {0, 0, 0}) {
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    const float x = m.positions[3 * v], y = m.positions[3 * v + 1], z = m.positions[3 * v + 2];
    for (int k = 0; k < 3; ++k)
      m.positions[3 * v + k] = r[3 * k] * x + r[3 * k + 1] * y + r[3 * k + 2] * z + t[k];
  }
  return m;
}

// For b = shuffled(a, seed, &old): A vertex v is B vertex truth[v].
std::vector<std::uint32_t> truth_of(const std::vector<std::uint32_t>& old) {
  std::vector<std::uint32_t> t(old.size());
  for (std::uint32_t i = 0; i < old.size(); ++i) t[old[i]] = i;
  return t;
}

void expect_valid(const QuadMesh& a, const QuadMesh& b, const MatchResult& r) {
  ASSERT_TRUE(r.isomorphic) << r.reason;
  std::string why;
  EXPECT_TRUE(verify_match(a, b, r, &why)) << why;
}

bool same_position(const QuadMesh& a, std::uint32_t v, const QuadMesh& b, std::uint32_t w) {
  for (int k = 0; k < 3; ++k)
    if (a.positions[3 * std::size_t(v) + k] != b.positions[3 * std::size_t(w) + k]) return false;
  return true;
}

// ---- Shuffled and morphed copies ----

TEST(Match, ShuffledCorpusMeshesMatchFaceByFace) {
  int n = 0, symmetric = 0, ambiguous = 0;
  for (const auto& path : testing::corpus()) {
    SCOPED_TRACE(path.string());
    QuadMesh m;
    if (!testing::read_valid(path, m)) continue;
    std::vector<std::uint32_t> old;
    const QuadMesh s = testing::shuffled(m, 7 + n, &old);
    const MatchResult r = match(m, s);
    expect_valid(m, s, r);
    EXPECT_EQ(r.cost, 0.0);
    // The nearest isomorphism of an exact copy is the shuffle itself, unless two isomorphisms put
    // every vertex on an equal position (then the result must say it is ambiguous).
    if (!r.ambiguous) {
      EXPECT_EQ(r.vertex, truth_of(old));
    }
    symmetric += r.isomorphisms > 1;
    ambiguous += r.ambiguous;
    ++n;
  }
  EXPECT_EQ(n, testing::expected_valid_count(testing::corpus()));
  std::printf("[ match    ] %d corpus meshes, %d with several isomorphisms, %d of them ambiguous\n", n,
              symmetric, ambiguous);
}

TEST(Match, GeneratedMeshesMatchTheirShuffles) {
  std::vector<QuadMesh> meshes = {testing::cube(3),
                                  testing::grid(4, 7),
                                  testing::periodic(8, 5, true, 0),
                                  testing::periodic(9, 6, true, 2),
                                  testing::periodic(7, 3, false, 0),
                                  box(1, 2, 3),
                                  sheared_cube(4, 2, 1)};
  QuadMesh several = testing::cube(2);
  testing::append(several, testing::cube(2), 5);
  testing::append(several, testing::grid(3, 2), 12);
  testing::append(several, testing::cube(2), -7);
  several.positions.insert(several.positions.end(), {100, 0, 0, 101, 0, 0});  // unreferenced
  meshes.push_back(several);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    SCOPED_TRACE(i);
    std::vector<std::uint32_t> old;
    const QuadMesh s = testing::shuffled(meshes[i], 100 + i, &old);
    const MatchResult r = match(meshes[i], s);
    expect_valid(meshes[i], s, r);
    EXPECT_FALSE(r.ambiguous);
    EXPECT_TRUE(r.exhaustive);
    EXPECT_EQ(r.vertex, truth_of(old));
  }
}

// The cost match() minimizes (Centering::kComponent), recomputed here for any vertex map `to`.
double component_centered_cost(const QuadMesh& a, const QuadMesh& b, const std::vector<std::uint32_t>& to) {
  const Adjacency adj = build_adjacency(a);
  const std::uint32_t none = adj.component_count;  // unreferenced vertices: centred on the mesh
  std::vector<std::uint32_t> comp(a.vertex_count(), none);
  for (std::size_t f = 0; f < a.face_count(); ++f)
    for (int c = 0; c < 4; ++c) comp[a.quads[4 * f + c]] = adj.face_component[f];
  std::vector<std::array<double, 7>> sum(none + 1, std::array<double, 7>{});  // A xyz, B xyz, count
  for (std::uint32_t v = 0; v < a.vertex_count(); ++v) {
    auto& s = sum[comp[v]];
    auto& m = sum[none];
    for (int k = 0; k < 3; ++k) {
      s[k] += a.positions[3 * v + k], s[3 + k] += b.positions[3 * std::size_t(to[v]) + k];
      if (comp[v] != none)
        m[k] += a.positions[3 * v + k], m[3 + k] += b.positions[3 * std::size_t(to[v]) + k];
    }
    s[6] += 1;
    if (comp[v] != none) sum[none][6] += 1;
  }
  double cost = 0;
  for (std::uint32_t v = 0; v < a.vertex_count(); ++v) {
    const auto& s = sum[comp[v]];
    for (int k = 0; k < 3; ++k) {
      const double d = (a.positions[3 * v + k] - s[k] / s[6]) -
                       (b.positions[3 * std::size_t(to[v]) + k] - s[3 + k] / s[6]);
      cost += d * d;
    }
  }
  return cost;
}

TEST(Match, MakeHumanBaseMatchesItsMorphs) {
  QSP_NEEDS_SHARED();
  const fs::path dir = testing::shared_dir() / "meshes";
  const QuadMesh base = read_mesh_file((dir / "mh_base.obj").string());
  ASSERT_EQ(build_adjacency(base).component_count, 154u);  // body plus 153 helpers, 125 of them 6-quad cubes
  int morphs = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("mh_base_morph_", 0) != 0 || e.path().extension() != ".obj") continue;
    SCOPED_TRACE(name);
    const QuadMesh morph = read_mesh_file(e.path().string());
    const MatchResult r = match(base, morph);
    expect_valid(base, morph, r);
    EXPECT_FALSE(r.ambiguous);
    // Morphs keep MakeHuman's numbering, so the identity is an isomorphism; the chosen one is at least
    // as near. They differ only where a morph turns or crushes a symmetric helper (a cube of the
    // skeleton helpers) far enough that another of its 24 turns is nearer.
    std::vector<std::uint32_t> identity(base.vertex_count());
    std::iota(identity.begin(), identity.end(), 0);
    const double id_cost = component_centered_cost(base, morph, identity);
    EXPECT_NEAR(r.cost, component_centered_cost(base, morph, r.vertex), 1e-9 * (1 + r.cost));
    EXPECT_LE(r.cost, id_cost * (1 + 1e-12));
    std::size_t moved = 0;
    for (std::uint32_t v = 0; v < identity.size(); ++v) moved += r.vertex[v] != v;
    EXPECT_LT(moved, base.vertex_count() / 100);
    std::printf("[ match    ] %s: %zu of %zu vertices not identity, cost %.4g vs identity %.4g\n",
                name.c_str(), moved, base.vertex_count(), r.cost, id_cost);
    // Renumbering the morph renumbers the answer and changes nothing else.
    std::vector<std::uint32_t> old;
    const QuadMesh shuffled_morph = testing::shuffled(morph, 5, &old);
    const MatchResult rs = match(base, shuffled_morph);
    expect_valid(base, shuffled_morph, rs);
    const auto truth = truth_of(old);
    for (std::uint32_t v = 0; v < identity.size(); ++v) ASSERT_EQ(rs.vertex[v], truth[r.vertex[v]]) << v;
    ++morphs;
  }
  EXPECT_GT(morphs, 0);
}

// ---- Mirrors ----

TEST(Match, MirroredCopyMatchesOnlyWithAMirrorSymmetry) {
  struct Case {
    const char* name;
    QuadMesh mesh;
    bool mirror_symmetric;
  };
  const std::vector<Case> cases = {
      {"L with equal arms", testing::polyomino({"##..", "##..", "####", "####"}), true},
      {"F pentomino", testing::polyomino({"..####", "..####", "####..", "####..", "..##..", "..##.."}),
       false},
      {"cube", testing::cube(3), true},
      {"box 1x2x3", box(1, 2, 3), true},
      {"torus, no twist", testing::periodic(9, 6, true, 0), true},
      {"torus, twist 2", testing::periodic(9, 6, true, 2), false},
      {"sheared cube", sheared_cube(3, 1, 1), false},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const QuadMesh m = mirrored(c.mesh);
    const MatchResult r = match(c.mesh, m);
    EXPECT_EQ(r.isomorphic, c.mirror_symmetric) << r.reason;
    EXPECT_EQ(brute_force_isomorphisms(c.mesh, m) > 0, c.mirror_symmetric);
    if (r.isomorphic) expect_valid(c.mesh, m, r);
  }
}

// Mirror::kHint says an F pentomino turned over would match; Mirror::kAccept matches it (every face
// reversed: A's corner c is B's corner (r - c) % 4), verify_match agrees, and reorder_like gives the
// reference's faces back; a mesh with a mirror symmetry still gets its orientation-preserving match.
TEST(Match, MirrorsAreHintedOrAcceptedOnlyWhenAsked) {
  const QuadMesh f = testing::polyomino({"..####", "..####", "####..", "####..", "..##..", "..##.."});
  std::vector<std::uint32_t> old;
  const QuadMesh m = testing::shuffled(mirrored(f), 4, &old);
  MatchOptions o;
  MatchResult r = match(f, m, o);
  EXPECT_FALSE(r.isomorphic);
  EXPECT_FALSE(r.mirror_would_match);  // not asked
  o.mirror = Mirror::kHint;
  r = match(f, m, o);
  EXPECT_FALSE(r.isomorphic);
  EXPECT_TRUE(r.mirror_would_match);
  o.mirror = Mirror::kAccept;
  r = match(f, m, o);
  ASSERT_TRUE(r.isomorphic) << r.reason;
  EXPECT_TRUE(r.mirrored);
  std::string why;
  EXPECT_TRUE(verify_match(f, m, r, &why)) << why;
  EXPECT_EQ(r.vertex, truth_of(old));  // the only one: the F has no symmetry
  r.rotation[0] ^= 1;
  EXPECT_FALSE(verify_match(f, m, r));
  r.rotation[0] ^= 1;
  const QuadMesh back = reorder_like(m, r);
  EXPECT_EQ(back.quads, f.quads);  // the reference's faces and orientation, the mirror's positions
  for (std::uint32_t v = 0; v < f.vertex_count(); ++v) ASSERT_TRUE(same_position(back, v, m, r.vertex[v]));
  // Not a mirror at all: no hint.
  o.mirror = Mirror::kHint;
  EXPECT_FALSE(match(f, testing::grid(3, 3), o).mirror_would_match);
  // A mesh with a mirror symmetry matches its mirror image preserving orientation, not mirrored.
  const QuadMesh cube = testing::cube(2);
  o.mirror = Mirror::kAccept;
  r = match(cube, mirrored(cube), o);
  EXPECT_TRUE(r.isomorphic);
  EXPECT_FALSE(r.mirrored);
}

// Small connected corpus meshes: match agrees with brute force on a mirrored copy and on the count.
TEST(Match, SmallCorpusMeshesAgreeWithBruteForce) {
  int n = 0;
  for (const auto& path : testing::corpus()) {
    QuadMesh m;
    Adjacency adj;
    if (!testing::read_valid(path, m, &adj)) continue;
    if (adj.component_count != 1 || m.face_count() > 600) continue;
    bool unreferenced = false;
    for (auto v : adj.valence) unreferenced |= v == 0;
    if (unreferenced) continue;
    SCOPED_TRACE(path.string());
    const QuadMesh s = testing::shuffled(m, 3);
    const MatchResult r = match(m, s);
    EXPECT_EQ(r.isomorphisms, brute_force_isomorphisms(m, s));
    const QuadMesh mm = mirrored(m);
    const MatchResult rm = match(m, mm);
    EXPECT_EQ(rm.isomorphic, brute_force_isomorphisms(m, mm) > 0) << rm.reason;
    if (rm.isomorphic) expect_valid(m, mm, rm);
    ++n;
  }
  EXPECT_GT(n, 5);
  std::printf("[ match    ] %d small connected corpus meshes checked against brute force\n", n);
}

// ---- Near misses ----

TEST(Match, ToriWithDifferentTwistsDiffer) {
  const QuadMesh a = testing::periodic(9, 6, true, 1), b = testing::periodic(9, 6, true, 2);
  const MatchResult r = match(a, b);
  EXPECT_FALSE(r.isomorphic);
  EXPECT_EQ(r.level, MatchLevel::kCode);
  EXPECT_NE(r.reason.find("twist"), std::string::npos) << r.reason;
  EXPECT_EQ(brute_force_isomorphisms(a, b), 0u);
  // Twist t and a - t are mirror images, not rotations, of each other.
  EXPECT_FALSE(match(testing::periodic(9, 6, true, 2), testing::periodic(9, 6, true, 7)).isomorphic);
}

TEST(Match, BoxesWithEqualCountsDiffer) {
  // 1x1x5 and 1x2x3: both 22 quads, 24 vertices, eight valence-3 corners.
  const QuadMesh a = box(1, 1, 5), b = box(1, 2, 3);
  ASSERT_EQ(a.face_count(), b.face_count());
  ASSERT_EQ(a.vertex_count(), b.vertex_count());
  const MatchResult r = match(a, b);
  EXPECT_FALSE(r.isomorphic);
  EXPECT_GE(r.level, MatchLevel::kSchematic) << r.reason;
  EXPECT_EQ(brute_force_isomorphisms(a, b), 0u);
}

TEST(Match, ReroutedStripsDiffer) {
  // Turning the top of a cube by one quad reroutes every vertical strip; by a whole side it does not.
  const QuadMesh cube = testing::cube(3);
  const QuadMesh turned = sheared_cube(3, 1, 3), sheared = sheared_cube(3, 1, 1);
  const MatchResult same = match(cube, turned);
  expect_valid(cube, turned, same);
  const MatchResult r = match(cube, sheared);
  EXPECT_FALSE(r.isomorphic);
  EXPECT_GE(r.level, MatchLevel::kSchematic) << r.reason;
  EXPECT_EQ(brute_force_isomorphisms(cube, sheared), 0u);
  // Shears by different amounts differ from each other too.
  EXPECT_FALSE(match(sheared_cube(4, 2, 1), sheared_cube(4, 2, 2)).isomorphic);
}

TEST(Match, CoarseLevelsAreReportedFirst) {
  QuadMesh two = testing::cube(2);
  testing::append(two, testing::cube(2), 4);
  EXPECT_EQ(match(testing::cube(2), two).level, MatchLevel::kComponentCount);
  EXPECT_EQ(match(testing::grid(4, 6), testing::grid(3, 8)).level, MatchLevel::kComponentSizes);
  // L and T tetrominoes: 10 vertices, 4 faces each; one concave corner against two.
  using Rows = std::vector<std::string>;
  const QuadMesh ell = testing::polyomino(Rows{"#..", "###"}), tee = testing::polyomino(Rows{"###", ".#."});
  const MatchResult r = match(ell, tee);
  EXPECT_EQ(r.level, MatchLevel::kExtraordinary) << r.reason;
  EXPECT_NE(r.reason.find("1 extraordinary"), std::string::npos) << r.reason;
  QuadMesh with_point = testing::cube(2);
  with_point.positions.insert(with_point.positions.end(), {9, 9, 9});
  EXPECT_EQ(match(with_point, testing::cube(2)).level, MatchLevel::kUnreferenced);
}

// ---- Symmetric meshes ----

TEST(Match, RefinedCubeHas24IsomorphismsAndUndoesARotation) {
  const QuadMesh a = testing::cube(4);
  // Rotate a shuffled copy by 90 degrees about z through the cube's centre: (x,y,z) -> (4-y, x, z).
  const QuadMesh b = transformed(testing::shuffled(a, 11), {0, -1, 0, 1, 0, 0, 0, 0, 1}, {4, 0, 0});
  const MatchResult r = match(a, b);
  expect_valid(a, b, r);
  EXPECT_EQ(r.isomorphisms, 24u);
  EXPECT_FALSE(r.ambiguous);
  EXPECT_EQ(r.cost, 0.0);
  // The nearest isomorphism sends every vertex to the vertex now at its place: it undoes the rotation.
  for (std::uint32_t v = 0; v < a.vertex_count(); ++v) ASSERT_TRUE(same_position(a, v, b, r.vertex[v])) << v;
  EXPECT_EQ(brute_force_isomorphisms(testing::cube(2), testing::cube(2)), 24u);
}

// A fan of n quads has n isomorphisms to its copy; they are bounded from a few probe vertices first
// (n starts of n probes each took minutes at n = 40,000). Its copy turned by three spokes, the nearest
// one sends every vertex to the copy's vertex now at its place, not to its own turned image.
TEST(Match, AFanTurnedBySpokesIsUndone) {
  constexpr int n = 600;
  const QuadMesh a = testing::fan(n);
  const float t = 6.2831853f * 3 / n, c = std::cos(t), s = std::sin(t);
  QuadMesh b = testing::shuffled(a, 5);
  for (std::size_t v = 0; v < b.vertex_count(); ++v) {
    const float x = b.positions[3 * v], y = b.positions[3 * v + 1];
    b.positions[3 * v] = c * x - s * y, b.positions[3 * v + 1] = s * x + c * y;
  }
  const MatchResult r = match(a, b);
  expect_valid(a, b, r);
  EXPECT_EQ(r.isomorphisms, static_cast<std::uint64_t>(n));
  EXPECT_TRUE(r.exhaustive);
  EXPECT_FALSE(r.ambiguous);
  for (std::uint32_t v = 0; v < a.vertex_count(); ++v) {
    const float px = a.positions[3 * v], py = a.positions[3 * v + 1];
    std::uint32_t nearest = 0;
    float d = HUGE_VALF;
    for (std::uint32_t w = 0; w < b.vertex_count(); ++w) {
      const float dx = b.positions[3 * w] - px, dy = b.positions[3 * w + 1] - py;
      if (dx * dx + dy * dy < d) d = dx * dx + dy * dy, nearest = w;
    }
    ASSERT_EQ(r.vertex[v], nearest) << v;
  }
}

TEST(Match, SymmetryCountsAgreeWithBruteForce) {
  for (const QuadMesh& m : {testing::grid(5, 5), testing::grid(5, 3), testing::periodic(8, 5, true, 0),
                            testing::periodic(6, 6, true, 0), testing::periodic(9, 6, true, 2),
                            testing::periodic(7, 3, false, 0), box(1, 2, 3), box(2, 2, 3)}) {
    const QuadMesh s = testing::shuffled(m, 1);
    const MatchResult r = match(m, s);
    expect_valid(m, s, r);
    EXPECT_EQ(r.isomorphisms, brute_force_isomorphisms(m, s)) << m.face_count();
  }
}

TEST(Match, EquallyNearIsomorphismsAreAmbiguous) {
  // A square grid against itself turned by 45 degrees: the turns by +-45 degrees are equally near.
  const QuadMesh a = testing::grid(4, 4);
  QuadMesh b = testing::shuffled(a, 2);
  const double c = std::sqrt(0.5);
  for (std::size_t v = 0; v < b.vertex_count(); ++v) {
    const double x = b.positions[3 * v] - 2.0, y = b.positions[3 * v + 1] - 2.0;
    b.positions[3 * v] = float(c * x - c * y);
    b.positions[3 * v + 1] = float(c * x + c * y);
  }
  const MatchResult r = match(a, b);
  expect_valid(a, b, r);
  EXPECT_EQ(r.isomorphisms, 4u);
  EXPECT_TRUE(r.ambiguous);
  // Turned by 30 degrees, turning back by 30 (not on by 60) is the unique nearest: each vertex goes
  // to its own turned copy.
  std::vector<std::uint32_t> old;
  QuadMesh d = testing::shuffled(a, 2, &old);
  const double cs = std::cos(0.5235987755982988), sn = std::sin(0.5235987755982988);
  for (std::size_t v = 0; v < d.vertex_count(); ++v) {
    const double x = d.positions[3 * v] - 2.0, y = d.positions[3 * v + 1] - 2.0;
    d.positions[3 * v] = float(cs * x - sn * y);
    d.positions[3 * v + 1] = float(sn * x + cs * y);
  }
  const MatchResult rd = match(a, d);
  EXPECT_FALSE(rd.ambiguous);
  EXPECT_EQ(rd.vertex, truth_of(old));
}

TEST(Match, InterchangeableComponentsPairByPlace) {
  // Three equal cubes, listed in another order in B and moved as a whole: each goes to its place.
  QuadMesh a = testing::cube(2);
  testing::append(a, testing::cube(2), 10);
  testing::append(a, testing::cube(2), 20);
  QuadMesh b = testing::cube(2);
  testing::append(b, testing::cube(2), 10);
  testing::append(b, testing::cube(2), 20);
  std::vector<std::uint32_t> old;
  b = transformed(testing::shuffled(b, 4, &old), {1, 0, 0, 0, 1, 0, 0, 0, 1}, {5, 5, 5});
  const MatchResult r = match(a, b);
  expect_valid(a, b, r);
  EXPECT_EQ(r.vertex, truth_of(old));
  EXPECT_EQ(r.isomorphisms, 6u * 24 * 24 * 24);
  EXPECT_FALSE(r.ambiguous);
  // Mesh centering removes the common translation too.
  MatchOptions mesh_centred;
  mesh_centred.centering = Centering::kMesh;
  const MatchResult rm = match(a, b, mesh_centred);
  EXPECT_EQ(rm.vertex, truth_of(old));
  EXPECT_NEAR(rm.cost, 0.0, 1e-9);
  // With raw positions the translation counts, but the pairing is still by nearest centroids.
  MatchOptions raw;
  raw.centering = Centering::kNone;
  const MatchResult rr = match(a, b, raw);
  expect_valid(a, b, rr);
  EXPECT_GT(rr.cost, 0.0);
}

TEST(Match, ManyEqualComponentsPairLinearly) {
  // 300 rings (more than the exact pairing handles, so they pair by sorted centroids), jittered so
  // that each ring's nearest turn is unique; 300! isomorphisms saturate the count.
  QuadMesh a;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> jitter(-0.05f, 0.05f);
  for (int i = 0; i < 300; ++i) {
    QuadMesh ring = testing::periodic(8, 3, i % 2 == 0, 0);
    for (float& x : ring.positions) x += jitter(rng);
    testing::append(a, ring, 10.0f * float(i % 20) + 0.5f * float(i / 20));
  }
  std::vector<std::uint32_t> old;
  const QuadMesh b = testing::shuffled(a, 6, &old);
  const MatchResult r = match(a, b);
  expect_valid(a, b, r);
  EXPECT_EQ(r.vertex, truth_of(old));
  EXPECT_EQ(r.isomorphisms, UINT64_MAX);
  EXPECT_FALSE(r.ambiguous);
  // 9000 loose quads (beyond greedy pairing: sorted centroids), each with 4 turns.
  QuadMesh quads;
  for (int i = 0; i < 9000; ++i) {
    const float x = float(i % 100) * 2, y = float(i / 100) * 2;
    quads.positions.insert(quads.positions.end(), {x, y, 0, x + 1, y, 0, x + 1.5f, y + 1, 0, x, y + 1, 0});
    for (std::uint32_t k = 0; k < 4; ++k) quads.quads.push_back(4 * i + k);
  }
  const QuadMesh qs = testing::shuffled(quads, 8, &old);
  const MatchResult rq = match(quads, qs);
  expect_valid(quads, qs, rq);
  EXPECT_EQ(rq.vertex, truth_of(old));
  EXPECT_TRUE(rq.exhaustive);
}

TEST(Match, PreparedMeshesAreRenumberedOnlyWhenScrambled) {
  const QuadMesh grid = testing::grid(80, 80);  // 6400 faces, file order row by row
  std::vector<std::uint32_t> old;
  const QuadMesh scrambled = testing::shuffled(grid, 3, &old);
  const MatchInput pg = prepare_match(grid), ps = prepare_match(scrambled);
  EXPECT_TRUE(pg.vertex_old.empty());
  EXPECT_FALSE(ps.vertex_old.empty());
  // Prepared once, matched twice; maps in the callers' numbering either way round.
  const MatchResult r = match(pg, ps), back = match(ps, pg);
  expect_valid(grid, scrambled, r);
  expect_valid(scrambled, grid, back);
  EXPECT_EQ(r.vertex, truth_of(old));
  EXPECT_EQ(r.vertex, match(grid, scrambled).vertex);
  // An invalid scrambled mesh reports the face as numbered in the caller's mesh.
  QuadMesh bad = scrambled;
  std::swap(bad.quads[4 * 777 + 1], bad.quads[4 * 777 + 3]);  // flip one face
  std::string expected, got;
  try {
    build_adjacency(bad);
  } catch (const Error& e) {
    expected = e.what();
  }
  try {
    prepare_match(bad);
  } catch (const Error& e) {
    got = e.what();
  }
  EXPECT_FALSE(expected.empty());
  EXPECT_EQ(got, expected);
}

// ---- Counts, order, reordering ----

// 30 interchangeable cubes have 24^30 * 30! isomorphisms: kept as a logarithm, not saturated, and printed
// readably; counts that fit stay exact, up to the edge (2 * 20! fits in 64 bits, 24 * 20! does not).
TEST(Match, CountsBeyond64BitsAreKeptAsALogarithm) {
  const QuadMesh many = testing::copies(testing::cube(2), 30, 10.0f);
  MatchResult r = match(many, testing::shuffled(many, 6));
  ASSERT_TRUE(r.isomorphic);
  EXPECT_FALSE(r.isomorphisms_exact);
  EXPECT_EQ(r.isomorphisms, UINT64_MAX);
  const double expected = 30 * std::log2(24.0) + std::lgamma(31.0) / std::log(2.0);
  EXPECT_NEAR(r.isomorphisms_log2, expected, 1e-9 * expected);
  EXPECT_EQ(isomorphism_count_text(r), "about 2^245.3 (6.8e73)");

  const QuadMesh three = testing::copies(testing::cube(2), 3, 10.0f);
  r = match(three, testing::shuffled(three, 7));
  EXPECT_TRUE(r.isomorphisms_exact);
  EXPECT_EQ(r.isomorphisms, 24u * 24u * 24u * 6u);
  EXPECT_EQ(r.isomorphisms_log2, std::log2(82944.0));
  EXPECT_EQ(isomorphism_count_text(r), "82944");

  const auto with_points = [](QuadMesh m, int points) {
    for (int i = 0; i < points; ++i) m.positions.insert(m.positions.end(), {float(i), 50, 50});
    return m;
  };
  const QuadMesh fits = with_points(testing::grid(2, 3), 20);  // 2 * 20!
  r = match(fits, fits);
  EXPECT_TRUE(r.isomorphisms_exact);
  EXPECT_EQ(r.isomorphisms, 2u * 2432902008176640000u);
  const QuadMesh over = with_points(testing::cube(2), 20);  // 24 * 20! > 2^64
  r = match(over, over);
  EXPECT_FALSE(r.isomorphisms_exact);
  EXPECT_NEAR(r.isomorphisms_log2, std::log2(24.0) + std::lgamma(21.0) / std::log(2.0), 1e-9);
  MatchResult none;
  EXPECT_EQ(isomorphism_count_text(none), "0");
}

// prefer_order: where the identity of indices is an isomorphism it wins over a nearer one (a cube whose
// copy was turned in place, components whose places were swapped, unreferenced vertices); without it
// the nearest wins. On a renumbered copy the result is still an isomorphism.
TEST(Match, PreferOrderKeepsTheIdentityWhereItIsAnIsomorphism) {
  std::vector<std::uint32_t> identity;
  const auto identity_of = [&](std::size_t n) {
    identity.resize(n);
    std::iota(identity.begin(), identity.end(), 0u);
    return identity;
  };
  MatchOptions keep;
  keep.prefer_order = true;
  // Turned by 90 degrees about z, same indices: the nearest isomorphism undoes the turn.
  const QuadMesh cube = testing::cube(4);
  const QuadMesh turned = transformed(cube, {0, -1, 0, 1, 0, 0, 0, 0, 1}, {4, 0, 0});
  MatchResult r = match(cube, turned);
  EXPECT_NE(r.vertex, identity_of(cube.vertex_count()));
  EXPECT_EQ(r.cost, 0.0);
  r = match(cube, turned, keep);
  expect_valid(cube, turned, r);
  EXPECT_EQ(r.vertex, identity_of(cube.vertex_count()));
  EXPECT_GT(r.cost, 0.0);
  EXPECT_FALSE(r.ambiguous);
  // Two equal cubes whose places are swapped (and an unreferenced vertex each, moved).
  QuadMesh a = testing::copies(testing::cube(2), 2, 10.0f), b = a;
  const std::size_t half = testing::cube(2).positions.size();
  std::swap_ranges(b.positions.begin(), b.positions.begin() + half, b.positions.begin() + half);
  a.positions.insert(a.positions.end(), {0, 0, 40, 0, 0, 50});
  b.positions.insert(b.positions.end(), {0, 0, 50, 0, 0, 40});
  r = match(a, b);
  EXPECT_NE(r.vertex, identity_of(a.vertex_count()));
  r = match(a, b, keep);
  expect_valid(a, b, r);
  EXPECT_EQ(r.vertex, identity_of(a.vertex_count()));
  // Renumbered: no identity to keep, still a valid isomorphism.
  const QuadMesh s = testing::shuffled(turned, 9);
  expect_valid(cube, s, match(cube, s, keep));
}

TEST(Match, ReorderLikeGivesTheReferenceFacesAndTheInputsPositions) {
  const QuadMesh ref = testing::cube(3);
  const QuadMesh in = transformed(testing::shuffled(ref, 21), {2, 0, 0, 0, 2, 0, 0, 0, 2});
  const MatchResult r = match(ref, in);
  const QuadMesh out = reorder_like(in, r);
  EXPECT_EQ(out.quads, ref.quads);
  for (std::uint32_t v = 0; v < ref.vertex_count(); ++v) ASSERT_TRUE(same_position(out, v, in, r.vertex[v]));
  try {
    reorder_like(in, match(ref, box(1, 2, 3)));
    ADD_FAILURE() << "not isomorphic, yet reordered";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUsage);
  }
}

// ---- CLI ----

class MatchCli : public testing::TempDirTest {
 protected:
  std::string write(const std::string& name, const QuadMesh& m) {
    testing::spit(p(name), write_obj(m));
    return p(name);
  }
  static std::vector<std::string> lines(std::istream&& in) {
    std::vector<std::string> out;
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
  }
  static std::vector<std::string> lines(const std::string& file) { return lines(std::ifstream(file)); }
  static std::vector<std::string> lines_of(const std::string& text) {
    return lines(std::istringstream(text));
  }
};

using testing::quote;
using testing::run_qsp;

TEST_F(MatchCli, MatchWritesTheMapAndExitsByResult) {
  const QuadMesh a = testing::cube(3);
  std::vector<std::uint32_t> old;
  const QuadMesh b = testing::shuffled(a, 8, &old);
  const std::string pa = write("a.obj", a), pb = write("b.obj", b), map = p("map.txt"), fmap = p("faces.txt");
  auto r = run_qsp("match " + quote(pa) + " " + quote(pb) + " -o " + quote(map) + " --faces " + quote(fmap));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("isomorphic"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("24 isomorphisms"), std::string::npos) << r.out;
  const auto vl = lines(map);
  ASSERT_EQ(vl.size(), a.vertex_count());
  const auto truth = truth_of(old);
  for (std::size_t v = 0; v < vl.size(); ++v) ASSERT_EQ(vl[v], std::to_string(truth[v])) << v;
  // Face map: "FACE ROTATION"; check it face by face.
  const auto fl = lines(fmap);
  ASSERT_EQ(fl.size(), a.face_count());
  for (std::size_t f = 0; f < fl.size(); ++f) {
    std::istringstream in(fl[f]);
    std::uint32_t g = 0, rot = 9;
    ASSERT_TRUE(in >> g >> rot) << fl[f];
    ASSERT_LT(g, b.face_count());
    for (std::uint32_t c = 0; c < 4; ++c)
      ASSERT_EQ(truth[a.quads[4 * f + c]], b.quads[4 * g + (c + rot) % 4]) << "face " << f;
  }
  // "-o -": the map on stdout, the report on stderr.
  r = run_qsp("match " + quote(pa) + " " + quote(pb) + " -o -");
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.substr(0, vl[0].size() + 1), vl[0] + "\n");
  EXPECT_NE(r.err.find("isomorphic"), std::string::npos);
  // Refuses to replace the map without -f.
  EXPECT_EQ(run_qsp("match " + quote(pa) + " " + quote(pb) + " -o " + quote(map)).exit_code, 3);
  EXPECT_EQ(run_qsp("match " + quote(pa) + " " + quote(pb) + " -f -o " + quote(map)).exit_code, 0);

  // Not isomorphic: 1, with the level on stdout.
  const std::string pc = write("c.obj", box(1, 2, 3)), pd = write("d.obj", box(1, 1, 5));
  r = run_qsp("match " + quote(pc) + " " + quote(pd));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("not isomorphic"), std::string::npos) << r.out;
  // A triangle is a polygon mesh (issue 20): not isomorphic to quads, by its face degrees.
  const std::string tri = p("tri.obj");
  testing::spit(tri, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  r = run_qsp("match " + quote(pa) + " " + quote(tri));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("not isomorphic: face degrees: "), std::string::npos) << r.out;
  // Errors are 2 or more: invalid mesh (a face repeating a vertex) 2, usage 2, missing file 3.
  const std::string bad = p("bad.obj");
  testing::spit(bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 2\n");
  EXPECT_EQ(run_qsp("match " + quote(pa) + " " + quote(bad)).exit_code, 2);
  EXPECT_EQ(run_qsp("match " + quote(pa)).exit_code, 2);
  EXPECT_EQ(run_qsp("match " + quote(pa) + " " + quote(p("missing.obj"))).exit_code, 3);
}

// Coordinates float32 does not hold (CAD exports) are rounded for matching, not read as a polygon mesh,
// whose matching does not search a symmetric mesh's isomorphisms for the nearest: a cube with ten digits
// and its copy turned a quarter about z still has the rotation undone.
TEST_F(MatchCli, CoordinatesOfManyDigitsStillChooseTheNearest) {
  const QuadMesh a = testing::cube(3);
  std::vector<std::uint32_t> old;
  const QuadMesh b = testing::shuffled(a, 3, &old);
  // Cube corners at k/3: "0.3333333333" holds more than float32 does.
  auto text = [](const QuadMesh& m, bool turn) {
    std::string out;
    char line[96];
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
      const double x = m.positions[3 * v] / 3, y = m.positions[3 * v + 1] / 3, z = m.positions[3 * v + 2] / 3;
      std::snprintf(line, sizeof line, "v %.10f %.10f %.10f\n", turn ? 1 - y : x, turn ? x : y, z);
      out += line;
    }
    for (std::size_t f = 0; f < m.face_count(); ++f)
      out += "f " + std::to_string(m.quads[4 * f] + 1) + " " + std::to_string(m.quads[4 * f + 1] + 1) + " " +
             std::to_string(m.quads[4 * f + 2] + 1) + " " + std::to_string(m.quads[4 * f + 3] + 1) + "\n";
    return out;
  };
  testing::spit(p("a.obj"), text(a, false));
  testing::spit(p("b.obj"), text(b, true));
  const auto r =
      run_qsp("match " + quote(p("a.obj")) + " " + quote(p("b.obj")) + " -o " + quote(p("map.txt")));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("24 isomorphisms; chose the nearest"), std::string::npos) << r.out;
  // A's vertex (x, y, z) goes to B's vertex now there: B's turned vertex of A's (y, 3 - x, z).
  const auto map = lines(p("map.txt"));
  ASSERT_EQ(map.size(), a.vertex_count());
  const auto truth = truth_of(old);
  for (std::uint32_t v = 0; v < a.vertex_count(); ++v) {
    const float x = a.positions[3 * v], y = a.positions[3 * v + 1], z = a.positions[3 * v + 2];
    std::uint32_t w = 0;
    while (w < a.vertex_count() &&
           !(a.positions[3 * w] == y && a.positions[3 * w + 1] == 3 - x && a.positions[3 * w + 2] == z))
      ++w;
    ASSERT_LT(w, a.vertex_count());
    ASSERT_EQ(map[v], std::to_string(truth[w])) << v;
  }
}

TEST_F(MatchCli, FingerprintGroupsFilesByTopology) {
  const std::string p1 = write("one.obj", testing::cube(2)),
                    p2 = write("two.obj", testing::shuffled(testing::cube(2), 3)),
                    p3 = write("three.obj", box(1, 2, 3));
  auto r = run_qsp("fingerprint " + quote(p1) + " " + quote(p2) + " " + quote(p3));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream in(r.out);
  std::string h1, f1, h2, f2, h3, f3;
  in >> h1 >> f1 >> h2 >> f2 >> h3 >> f3;
  EXPECT_EQ(h1.size(), 16u);
  EXPECT_EQ(h1, h2);
  EXPECT_NE(h1, h3);
  EXPECT_EQ(f1, p1);
  EXPECT_EQ(f3, p3);
  r = run_qsp("fingerprint --group " + quote(p1) + " " + quote(p3) + " " + quote(p2));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Groups in order of first appearance, separated by a blank line.
  EXPECT_EQ(r.out, h1 + "  " + p1 + "\n" + h1 + "  " + p2 + "\n\n" + h3 + "  " + p3 + "\n");
}

TEST_F(MatchCli, ReorderGivesTheReferenceOrder) {
  const QuadMesh ref = testing::cube(3);
  std::vector<std::uint32_t> old;
  const QuadMesh in = transformed(testing::shuffled(ref, 21, &old), {2, 0, 0, 0, 2, 0, 0, 0, 2});  // scaled
  const std::string pr = write("ref.obj", ref), pi = write("in.obj", in), out = p("out.obj");
  auto r = run_qsp("reorder --like " + quote(pr) + " " + quote(pi) + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const QuadMesh got = read_mesh_file(out);
  EXPECT_EQ(got.quads, ref.quads);  // REF's faces, corners and vertex numbers
  const auto truth = truth_of(old);
  ASSERT_EQ(got.vertex_count(), ref.vertex_count());
  for (std::uint32_t v = 0; v < ref.vertex_count(); ++v)
    ASSERT_TRUE(same_position(got, v, in, truth[v])) << v;
  // Refuses to overwrite without -f; -f replaces.
  EXPECT_EQ(run_qsp("reorder --like " + quote(pr) + " " + quote(pi) + " -o " + quote(out)).exit_code, 3);
  EXPECT_EQ(run_qsp("reorder --like " + quote(pr) + " " + quote(pi) + " -f -o " + quote(out)).exit_code, 0);
  // Not isomorphic: 1.
  const std::string pc = write("c.obj", box(1, 2, 3));
  EXPECT_EQ(run_qsp("reorder --like " + quote(pr) + " " + quote(pc) + " -o " + quote(p("x.obj"))).exit_code,
            1);
}

// An all-quad IN with texture coordinates is read by the exact reader (or decoded from its .qsp as polygons),
// yet matched as quads, which
// searches a symmetric mesh's isomorphisms for the nearest (the polygon way took one of them): a fan of
// 600 quads against its copy turned by three spokes and moved a little gets each vertex the copy's
// vertex now at its place, and each corner's texture coordinate comes with its vertex.
TEST_F(MatchCli, ReorderOfQuadsWithTextureCoordinatesChoosesTheNearest) {
  constexpr int n = 600;
  const QuadMesh ref = testing::fan(n);
  std::vector<std::uint32_t> old;
  const QuadMesh in = testing::shuffled(ref, 4, &old);
  const float t = 6.2831853f * 3 / n, c = std::cos(t), s = std::sin(t);
  std::string text;
  std::vector<std::array<float, 3>> in_pos;  // as OUT's reader reads the text back
  char line[128];
  for (std::size_t v = 0; v < in.vertex_count(); ++v) {  // turned, moved by up to 0.0005
    const float x = in.positions[3 * v], y = in.positions[3 * v + 1], e = 0.0005f * std::sin(7.0f * v);
    std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", c * x - s * y + e, s * x + c * y - e, 0.0);
    text += line;
    std::istringstream back(std::string(line).substr(2));
    in_pos.emplace_back();
    back >> in_pos.back()[0] >> in_pos.back()[1] >> in_pos.back()[2];
  }
  for (std::size_t v = 0; v < in.vertex_count(); ++v) text += "vt " + std::to_string(v) + " 0.5\n";
  for (std::size_t f = 0; f < in.face_count(); ++f) {
    text += "f";
    for (int k = 0; k < 4; ++k) {
      const std::string i = std::to_string(in.quads[4 * f + k] + 1);
      text.append(" ").append(i).append("/").append(i);
    }
    text += "\n";
  }
  testing::spit(p("in.obj"), text);
  const std::string pr = write("ref.obj", ref), out = p("out.obj");
  const auto r = run_qsp("reorder --like " + quote(pr) + " " + quote(p("in.obj")) + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("may be symmetric"), std::string::npos) << r.err;
  // OUT: REF's faces; its vertex v near REF's vertex v; a corner's texture coordinate u names the IN
  // vertex that came there.
  std::vector<std::array<float, 3>> pos;
  std::vector<float> u;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> corners;  // (vertex, texture coordinate)
  std::ifstream file(out);
  for (std::string l; std::getline(file, l);) {
    std::istringstream in_line(l);
    std::string kind;
    in_line >> kind;
    if (kind == "v") {
      std::array<float, 3> q{};
      in_line >> q[0] >> q[1] >> q[2];
      pos.push_back(q);
    } else if (kind == "vt") {
      u.push_back(0);
      in_line >> u.back();
    } else if (kind == "f") {
      for (std::string w; in_line >> w;)
        corners.emplace_back(std::stoul(w) - 1, std::stoul(w.substr(w.find('/') + 1)) - 1);
    }
  }
  ASSERT_EQ(pos.size(), ref.vertex_count());
  ASSERT_EQ(corners.size(), ref.quads.size());
  for (std::size_t k = 0; k < corners.size(); ++k) {
    ASSERT_EQ(corners[k].first, ref.quads[k]) << "corner " << k;
    const auto w = static_cast<std::uint32_t>(u.at(corners[k].second));  // IN's vertex
    ASSERT_LT(w, in.vertex_count());
    ASSERT_EQ(pos[corners[k].first], in_pos[w]) << "corner " << k;
  }
  for (std::uint32_t v = 0; v < ref.vertex_count(); ++v)
    ASSERT_LT(std::hypot(pos[v][0] - ref.positions[3 * v], pos[v][1] - ref.positions[3 * v + 1]), 0.002) << v;
  // match too, where IN is its .qsp, which decodes (with its texture coordinates) as polygons of quads.
  ASSERT_EQ(run_qsp("compress " + quote(p("in.obj")) + " -o " + quote(p("in.qsp"))).exit_code, 0);
  const auto m = run_qsp("match " + quote(pr) + " " + quote(p("in.qsp")));
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_NE(m.out.find("600 isomorphisms; chose the nearest"), std::string::npos) << m.out;
}

// Files of every released format version fingerprint as their mesh: the goldens of the current
// encoder, and those of older released versions where a later one changed the bytes (testdata/golden/
// vX.Y/; golden/v3.5/normals and v3.16/normals are checked in test_normals.cpp).
TEST_F(MatchCli, OlderFormatFilesFingerprintAsTheirMesh) {
  const std::string golden = std::string(QSP_TESTDATA_DIR) + "/golden/";
  int seen = 0;
  for (const char* name : {"cube_4", "l_shape", "multi_component", "torus_twist_9x6_t2", "annulus_12x3"}) {
    std::string cmd = "fingerprint " + quote(golden + name + ".obj") + " " + quote(golden + name + ".qsp");
    int files = 2;
    for (const char* dir : {"v3.0"}) {
      const std::string old = (fs::path(golden) / dir / (std::string(name) + ".qsp")).string();
      if (!fs::exists(old)) continue;
      cmd += " " + quote(old);
      ++files;
    }
    const auto r = run_qsp(cmd);
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    const auto out = lines_of(r.out);
    ASSERT_EQ(out.size(), static_cast<std::size_t>(files)) << r.out;
    for (const auto& l : out) EXPECT_EQ(l.substr(0, 16), out[0].substr(0, 16)) << name << "\n" << r.out;
    seen += files;
  }
  EXPECT_GE(seen, 10);
}

TEST_F(MatchCli, QspFilesFingerprintMatchAndReorder) {
  // A shape whose greedy partition (compress --partition greedy) differs from the motorcycle graph.
  const QuadMesh m = testing::polyomino(std::vector<std::string>{
      "######..", "######..", "########", "########", "########", "########", "..######", "..######"});
  std::vector<std::uint32_t> old;
  const QuadMesh s = testing::shuffled(m, 12, &old);
  const std::string pm = write("m.obj", m), ps = write("s.obj", s), qm = p("m.qsp"), qg = p("g.qsp");
  ASSERT_EQ(run_qsp("compress " + quote(pm) + " " + quote(qm)).exit_code, 0);
  ASSERT_EQ(run_qsp("compress --partition greedy " + quote(pm) + " " + quote(qg)).exit_code, 0);
  auto r = run_qsp("fingerprint " + quote(pm) + " " + quote(qm) + " " + quote(qg) + " " + quote(ps));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string fp = r.out.substr(0, 16);
  EXPECT_EQ(r.out,
            fp + "  " + pm + "\n" + fp + "  " + qm + "\n" + fp + "  " + qg + "\n" + fp + "  " + ps + "\n");
  // match on a .qsp numbers its vertices as decompress writes them.
  const std::string back = p("back.obj");
  ASSERT_EQ(run_qsp("decompress " + quote(qm) + " " + quote(back)).exit_code, 0);
  const QuadMesh decoded = read_mesh_file(back);
  const std::string map = p("map.txt");
  r = run_qsp("match " + quote(qm) + " " + quote(ps) + " -o " + quote(map));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto vl = lines(map);
  ASSERT_EQ(vl.size(), decoded.vertex_count());
  for (std::uint32_t v = 0; v < decoded.vertex_count(); ++v)
    ASSERT_TRUE(same_position(decoded, v, s, std::stoul(vl[v]))) << v;
  // reorder into a .qsp keeps REF's order through decompress.
  const std::string out = p("out.qsp"), out_obj = p("out.obj");
  ASSERT_EQ(run_qsp("reorder --like " + quote(pm) + " " + quote(ps) + " -o " + quote(out)).exit_code, 0);
  ASSERT_EQ(run_qsp("decompress " + quote(out) + " " + quote(out_obj)).exit_code, 0);
  EXPECT_EQ(read_mesh_file(out_obj).quads, m.quads);
  // A damaged .qsp is an error (2), not "not isomorphic".
  std::string bytes = read_file_bytes(qm);
  bytes[bytes.size() / 2] ^= 0x40;
  testing::spit(p("bad.qsp"), bytes);
  EXPECT_EQ(run_qsp("match " + quote(p("bad.qsp")) + " " + quote(ps)).exit_code, 2);
  EXPECT_EQ(run_qsp("fingerprint " + quote(p("bad.qsp"))).exit_code, 1);
}

}  // namespace
}  // namespace qsp
