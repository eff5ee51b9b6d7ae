// Polygon meshes cut into their manifold, oriented quad submesh: hand-checked cases, the rules'
// invariance under renumbering, gluing back, and every shared mesh (read by a reader of this file's own:
// qsp's OBJ reader refuses non-quads).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/partition.h"
#include "qsp/submesh.h"
#include "support/corpus.h"
#include "support/polygon.h"
#include "support/schematic_counts.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::Grid;
using testing::Poly;
using Sizes = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

QuadSubmesh submesh(const Poly& p) { return quad_submesh(p.offsets, p.corners, p.nv, p.positions); }

void check_glue(const Poly& p, const QuadSubmesh& s);
void check_cut(const Poly& p);

// The submesh, with check_glue and check_cut run on it.
QuadSubmesh checked(const Poly& p) {
  QuadSubmesh s = submesh(p);
  check_glue(p, s);
  check_cut(p);
  return s;
}

// The motorcycle partition of the quad submesh, validated, as counts (schematic vertices, edges,
// patches, holes, sizes, kinds), and its extraordinary vertices as original vertex indices.
struct Summary : testing::SchematicCounts {
  std::set<std::uint32_t> extraordinary;
};

Summary summarize(const QuadSubmesh& s) {
  const Partition p = partition_motorcycle(s.adjacency);
  for (const auto& part : p.components)
    EXPECT_EQ(validate(part, &s.adjacency), "") << "component " << part.component;
  Summary out{testing::schematic_counts(p), {}};
  for (std::uint32_t v : extraordinary_vertices(s.adjacency)) out.extraordinary.insert(s.vertex_original[v]);
  return out;
}

// The hand-worked numbers: the extraordinary vertices (original indices), the schematic's vertices,
// edges and patches, and (unless empty) the patch sizes.
Summary expect_partition(const QuadSubmesh& s, const std::set<std::uint32_t>& extraordinary, std::uint32_t x,
                         std::uint32_t e, std::uint32_t patches, const Sizes& sizes = {}) {
  Summary k = summarize(s);
  EXPECT_EQ(k.extraordinary, extraordinary);
  EXPECT_EQ(k.x, x);
  EXPECT_EQ(k.e, e);
  EXPECT_EQ(k.patches, patches);
  if (!sizes.empty()) {
    EXPECT_EQ(k.sizes, sizes);
  }
  return k;
}

// Checks what holds for every result: faces once each, gluing back gives the input, interior vertices
// are used by no quad, every non-quad corner lies on its region's interior or on a loop it touches.
void check_glue(const Poly& p, const QuadSubmesh& s) {
  const std::uint32_t nq = static_cast<std::uint32_t>(s.mesh.vertex_count());
  ASSERT_EQ(s.corner_vertex.size(), p.corners.size());
  for (std::size_t c = 0; c < p.corners.size(); ++c)
    ASSERT_EQ(s.vertex_original[s.corner_vertex[c]], p.corners[c]) << "corner " << c;
  std::vector<int> seen(p.face_count(), 0);
  ASSERT_EQ(s.quad_face.size(), s.mesh.face_count());
  for (std::uint32_t q = 0; q < s.quad_face.size(); ++q) {
    const std::uint32_t f = s.quad_face[q];
    ASSERT_EQ(p.degree(f), 4u);
    ++seen[f];
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(s.vertex_original[s.mesh.quads[4 * q + k]], p.corners[p.offsets[f] + k]) << "quad " << q;
  }
  std::set<std::uint32_t> interior_seen;
  for (std::size_t r = 0; r < s.regions.size(); ++r) {
    const NonQuadRegion& region = s.regions[r];
    EXPECT_TRUE(std::is_sorted(region.faces.begin(), region.faces.end()));
    EXPECT_TRUE(std::adjacent_find(region.loops.begin(), region.loops.end()) == region.loops.end());
    EXPECT_TRUE(std::is_sorted(region.loops.begin(), region.loops.end()));
    const std::set<std::uint32_t> interior(region.interior.begin(), region.interior.end());
    for (std::uint32_t v : region.interior) {
      EXPECT_GE(v, nq);
      EXPECT_TRUE(interior_seen.insert(v).second) << "interior vertex in two regions";
    }
    for (std::uint32_t f : region.faces) {
      EXPECT_NE(p.degree(f), 4u);
      ++seen[f];
      for (std::uint32_t c = p.offsets[f]; c < p.offsets[f + 1]; ++c) {
        const std::uint32_t v = s.corner_vertex[c];
        if (v >= nq) {
          EXPECT_TRUE(interior.count(v)) << "face " << f << " uses another region's interior vertex";
        } else {
          const std::uint32_t h = s.adjacency.vertex_halfedge[v];
          ASSERT_TRUE(s.adjacency.is_exterior(h)) << "face " << f << " touches an inner quad vertex";
          const std::uint32_t loop = s.exterior_loop[h - 4 * s.adjacency.face_count];
          EXPECT_TRUE(std::binary_search(region.loops.begin(), region.loops.end(), loop));
        }
      }
    }
  }
  EXPECT_EQ(interior_seen.size(), s.vertex_original.size() - nq);
  for (std::uint32_t f = 0; f < p.face_count(); ++f) EXPECT_EQ(seen[f], 1) << "face " << f;
  // Every loop is named by its smallest exterior half-edge.
  for (std::size_t i = 0; i < s.exterior_loop.size(); ++i)
    EXPECT_LE(s.loop_halfedge[s.exterior_loop[i]], 4 * s.adjacency.face_count + i);
}

// Independent check that a polygon mesh over `corners` is a consistently oriented manifold: each
// directed edge once, and around each vertex one fan (counted by walking a std::map rotation).
void expect_oriented_manifold(const std::vector<std::uint32_t>& offsets,
                              const std::vector<std::uint32_t>& corners, std::uint32_t nv) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> directed;  // (from, to) -> corner
  std::vector<std::uint32_t> next(corners.size()), prev(corners.size());
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
    for (std::uint32_t c = offsets[f]; c < offsets[f + 1]; ++c) {
      next[c] = c + 1 == offsets[f + 1] ? offsets[f] : c + 1;
      prev[next[c]] = c;
    }
  for (std::uint32_t c = 0; c < corners.size(); ++c)
    EXPECT_TRUE(directed.emplace(std::make_pair(corners[c], corners[next[c]]), c).second)
        << "directed edge " << corners[c] << "-" << corners[next[c]] << " twice";
  // Fans: corner c continues (counter-clockwise) to the corner leaving along the reverse of its entering
  // edge.
  std::vector<int> fans(nv, 0);
  std::vector<char> done(corners.size(), 0);
  for (std::uint32_t c0 = 0; c0 < corners.size(); ++c0) {
    if (done[c0]) continue;
    ++fans[corners[c0]];
    auto step = [&](std::uint32_t c, bool ccw) -> std::int64_t {
      const auto it =
          ccw ? directed.find({corners[c], corners[prev[c]]}) : directed.find({corners[next[c]], corners[c]});
      if (it == directed.end()) return -1;
      return ccw ? it->second : next[it->second];
    };
    done[c0] = 1;
    for (bool ccw : {true, false})
      for (std::int64_t c = step(c0, ccw); c >= 0 && !done[c]; c = step(static_cast<std::uint32_t>(c), ccw))
        done[c] = 1;
  }
  for (std::uint32_t v = 0; v < nv; ++v) EXPECT_LE(fans[v], 1) << "vertex " << v << " has several fans";
}

void check_cut(const Poly& p) {
  const ManifoldCut cut = cut_manifold(p.offsets, p.corners, p.nv);
  ASSERT_EQ(cut.corners.size(), p.corners.size());
  for (std::size_t c = 0; c < p.corners.size(); ++c)
    EXPECT_EQ(cut.copy_original[cut.corners[c]], p.corners[c]);
  for (std::uint32_t v = 0; v < p.nv; ++v) EXPECT_EQ(cut.copy_original[v], v);
  expect_oriented_manifold(p.offsets, cut.corners, static_cast<std::uint32_t>(cut.copy_original.size()));
}

// ---- Hand-checked cases. Grid vertices are named (x, y); D is the deficiency in the quad submesh.

// A 5x4 grid without cell (0,3) (a notch), cells (0,1) and (1,1) split into triangles: a hole that
// runs into the left side. D: r = (1,3), (2,2), (2,1) have 4 edges on the boundary: D = -1,
// extraordinary; (0,0), (5,0), (5,4), (1,4), (0,3), (0,2), (0,1) are corners (D = +1); sum 4 (a disk).
// Particles, step 1: r east reaches (2,3) with the one from (2,2) going north; the cell between their
// tracks is (1,2), whose own half-edge into (2,3) comes from (2,2): the north one goes on to (2,4).
// r south reaches (1,2), a hole vertex with 3 edges (D = 0, ordinary): it stops there, at the
// triangles. (2,2) east and (2,1) east run to x = 5; (2,1) south stops at (2,0).
// Patches: [0,2]x[0,1], [2,5]x[0,1], [2,5]x[1,2], [2,5]x[2,4], and the cells (0,2), (1,2), (1,3).
// Schematic vertices: the 7 corners, the 3 extraordinary vertices, and (2,0), (5,1), (5,2), (1,2),
// (2,3), (2,4): 16. Edges: the boundary loop (22 mesh edges) in 15 pieces, plus the 7 tracks between
// schematic vertices: 22. 16 - 22 + (7 patches + 1 hole) = 2.
TEST(Submesh, ParticlesStopAtATriangle) {
  Grid g = Grid::make(5, 4, [](int i, int j) {
    if (i == 0 && j == 3) return '.';
    return j == 1 && i <= 1 ? 't' : 'q';
  });
  const QuadSubmesh s = checked(g.p);
  EXPECT_EQ(s.counts.quads, 17u);
  EXPECT_EQ(s.counts.triangles, 4u);
  EXPECT_EQ(s.counts.cut_vertices, 0u);
  const Summary k = expect_partition(s, {g.id(1, 3), g.id(2, 2), g.id(2, 1)}, 16u, 22u, 7u);
  EXPECT_EQ(k.holes, 1u);
  EXPECT_EQ(k.sizes, (Sizes{{1, 1}, {1, 1}, {1, 1}, {1, 2}, {1, 3}, {1, 3}, {2, 3}}));
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_EQ(s.regions[0].faces.size(), 4u);
  EXPECT_TRUE(s.regions[0].interior.empty());
  EXPECT_EQ(s.regions[0].loops.size(), 1u);
  EXPECT_EQ(s.loop_halfedge.size(), 1u);  // the hole opens into the outer boundary
  // The notch's far vertex (0,4) is in no face: kept, unreferenced, as in any quad mesh.
  EXPECT_EQ(s.adjacency.valence[g.id(0, 4)], 0u);
}

// Same hole in the middle of a 3x3 grid (cell (1,1) as two triangles): its four corners have D = -1
// and send one particle each way to the outer boundary, one step. Every vertex becomes a schematic
// vertex (16), every mesh edge a schematic edge (12 outer + 4 hole + 8 tracks = 24), 8 unit patches.
TEST(Submesh, TriangleHoleInAGrid) {
  Grid g = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? 't' : 'q'; });
  const QuadSubmesh s = checked(g.p);
  const Summary k = expect_partition(s, {g.id(1, 1), g.id(2, 1), g.id(1, 2), g.id(2, 2)}, 16u, 24u, 8u);
  EXPECT_EQ(k.holes, 2u);
  EXPECT_EQ(k.sizes, Sizes(8, {1, 1}));
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_EQ(s.regions[0].loops.size(), 1u);
  EXPECT_EQ(s.loop_halfedge.size(), 2u);
}

// A closed "UV sphere": poles N, S with 6 triangles each, three rings of 6, two rows of quads. The
// ring vertices next to a pole keep 3 edges on the boundary (D = 0): the quad submesh is a structured
// annulus (6 around, 2 rows), no extraordinary vertex, one patch. The poles are the regions' interior.
TEST(Submesh, TriangleFanPoleLeavesAStructuredAnnulus) {
  Poly p;
  const std::uint32_t n = 6, north = 18, south = 19;
  auto ring = [&](std::uint32_t k, std::uint32_t i) { return k * n + i % n; };
  p.nv = 3 * n + 2;
  for (std::uint32_t i = 0; i < n; ++i) p.face({north, ring(0, i), ring(0, i + 1)});
  for (std::uint32_t k = 0; k < 2; ++k)
    for (std::uint32_t i = 0; i < n; ++i)
      p.face({ring(k, i), ring(k + 1, i), ring(k + 1, i + 1), ring(k, i + 1)});
  for (std::uint32_t i = 0; i < n; ++i) p.face({south, ring(2, i + 1), ring(2, i)});
  const QuadSubmesh s = checked(p);
  const Summary k = summarize(s);
  EXPECT_TRUE(k.extraordinary.empty());
  ASSERT_EQ(k.kinds, std::vector<ComponentKind>{ComponentKind::kAnnulus});
  const Partition part = partition_motorcycle(s.adjacency);
  EXPECT_EQ(part.components[0].a * part.components[0].b, 12u);
  EXPECT_EQ(s.mesh.vertex_count(), 18u);  // the poles are in no quad
  ASSERT_EQ(s.regions.size(), 2u);
  for (const auto& r : s.regions) {
    EXPECT_EQ(r.faces.size(), 6u);
    ASSERT_EQ(r.interior.size(), 1u);
    EXPECT_EQ(r.loops.size(), 1u);
  }
  EXPECT_EQ(s.vertex_original[s.regions[0].interior[0]], north);
  EXPECT_EQ(s.vertex_original[s.regions[1].interior[0]], south);
  EXPECT_NE(s.regions[0].loops, s.regions[1].loops);
  EXPECT_EQ(s.counts.triangles, 12u);
  EXPECT_EQ(s.counts.extra_copies, 0u);
}

// A 4x4 grid whose middle 2x2 block is one region: three hexagons, a pentagon and a triangle around
// the centre (2,2) and four new spoke points, 5 interior vertices. The quad submesh is a ring of
// width 1: the block's corners (1,1), (3,1), (3,3), (1,3) have D = -1 and send one particle each way
// to the boundary; its side midpoints keep 3 edges (D = 0). Schematic: 4 outer corners, 4 hole
// corners, 8 track ends = 16 vertices; 12 outer + 4 hole (length 2) + 8 track edges = 24; patches:
// 4 corner cells (1x1), 4 side strips (1x2).
TEST(Submesh, NgonRegionWithInteriorVertices) {
  Grid g =
      Grid::make(4, 4, [](int i, int j) { return (i == 1 || i == 2) && (j == 1 || j == 2) ? '.' : 'q'; });
  Poly& p = g.p;
  const std::uint32_t m = g.id(2, 2), pe = 25, pn = 26, pw = 27, ps = 28;
  p.nv = 29;
  p.face({pe, g.id(3, 2), g.id(3, 3)});                     // triangle
  p.face({m, pe, g.id(3, 3), g.id(2, 3), pn});              // pentagon
  p.face({m, pn, g.id(2, 3), g.id(1, 3), g.id(1, 2), pw});  // hexagons
  p.face({m, pw, g.id(1, 2), g.id(1, 1), g.id(2, 1), ps});
  p.face({m, ps, g.id(2, 1), g.id(3, 1), g.id(3, 2), pe});
  const QuadSubmesh s = checked(p);
  EXPECT_EQ(s.counts.quads, 12u);
  EXPECT_EQ(s.counts.triangles, 1u);
  EXPECT_EQ(s.counts.ngons, 4u);
  const Summary k = expect_partition(s, {g.id(1, 1), g.id(3, 1), g.id(3, 3), g.id(1, 3)}, 16u, 24u, 8u,
                                     Sizes{{1, 1}, {1, 1}, {1, 1}, {1, 1}, {1, 2}, {1, 2}, {1, 2}, {1, 2}});
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_EQ(s.regions[0].faces.size(), 5u);
  std::set<std::uint32_t> interior;
  for (std::uint32_t v : s.regions[0].interior) interior.insert(s.vertex_original[v]);
  EXPECT_EQ(interior, (std::set<std::uint32_t>{m, pe, pn, pw, ps}));
  EXPECT_EQ(s.regions[0].loops.size(), 1u);
}

// A 4x4 grid with cells (2,2) and (1,1) as triangles: around v = (2,2) the faces are triangle, quad
// (1,2), triangle, quad (2,1), so v's quads form two fans and v is cut into two copies, each a corner
// (2 edges, D = +1). The two holes become one boundary loop through both copies; the quad submesh is
// an annulus (26 vertices, 40 edges, 14 quads). D = -1 at the holes' other corners e = (3,2),
// ne = (3,3), n = (2,3), w = (1,2), sw = (1,1), s = (2,1): 12 particles. At (3,1) the one going south
// from e meets the one going east from s; the cell between is (2,1), whose half-edge into (3,1) comes
// from s: s's goes on to (4,1). Symmetrically at (1,3) n's (going west) goes on to (0,3). Patches:
// [2,4]x[0,1] and [0,2]x[3,4] (1x2) and ten unit cells; every vertex is a schematic vertex but (3,0)
// and (1,4): 24; edges: 38 cut mesh edges, two pairs joined at (3,0) and (1,4): 36.
TEST(Submesh, VertexCutApartByTriangles) {
  Grid g =
      Grid::make(4, 4, [](int i, int j) { return (i == 2 && j == 2) || (i == 1 && j == 1) ? 't' : 'q'; });
  const QuadSubmesh s = checked(g.p);
  EXPECT_EQ(s.counts.cut_vertices, 1u);
  EXPECT_EQ(s.counts.extra_copies, 1u);
  EXPECT_EQ(s.mesh.vertex_count(), 26u);
  const std::uint32_t v = g.id(2, 2);
  EXPECT_EQ(std::count(s.vertex_original.begin(), s.vertex_original.end(), v), 2);
  const Summary k = expect_partition(
      s, {g.id(3, 2), g.id(3, 3), g.id(2, 3), g.id(1, 2), g.id(1, 1), g.id(2, 1)}, 24u, 36u, 12u);
  Sizes sizes(10, {1, 1});
  sizes.push_back({1, 2});
  sizes.push_back({1, 2});
  EXPECT_EQ(k.sizes, sizes);
  EXPECT_EQ(s.loop_halfedge.size(), 2u);
  ASSERT_EQ(s.regions.size(), 2u);
  EXPECT_EQ(s.regions[0].loops, s.regions[1].loops);  // both fill the one merged hole
  for (std::uint32_t c = 0; c < g.p.corners.size(); ++c)
    if (g.p.corners[c] == v) {
      EXPECT_EQ(s.adjacency.valence[s.corner_vertex[c]], 2u);
    }
}

// A 2x2 sheet and a fin quad on its edge (1,0)-(1,1): three faces on one edge. Each keeps its own copy
// of the edge: (1,0) gets three copies (cells (0,0), (1,0), the fin), (1,1) two (the sheet's one open
// fan, the fin). The sheet is slit from (1,0) to its centre, which now has 5 edges on the boundary
// (D = -2): its 3 particles run one step each to the sides. Sheet: 10 vertices, 13 edges, 4 unit
// patches, all schematic; the fin: one unit patch, 4 + 4. Total 14 vertices, 17 edges, 5 patches.
TEST(Submesh, NonManifoldEdgeWithThreeQuads) {
  Grid g = Grid::make(2, 2, [](int, int) { return 'q'; });
  g.p.nv = 11;
  g.p.face({g.id(1, 0), g.id(1, 1), 10, 9});
  const QuadSubmesh s = checked(g.p);
  EXPECT_EQ(s.counts.cut_edges, 1u);
  EXPECT_EQ(s.counts.cut_vertices, 2u);
  EXPECT_EQ(s.counts.extra_copies, 3u);
  const Summary k = expect_partition(s, {g.id(1, 1)}, 14u, 17u, 5u, Sizes(5, {1, 1}));
  EXPECT_EQ(s.adjacency.component_count, 2u);
  EXPECT_TRUE(s.regions.empty());
}

// A 3x3 grid whose middle cell runs clockwise: its four edges are traversed the same way by both
// neighbours, so all four are cut and its corners get a second copy. The ring left behind is the
// triangle-hole case (16, 24, 8 patches); the flipped cell is a unit patch of its own (4, 4, 1).
TEST(Submesh, MisorientedFaceInAGrid) {
  Grid g = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? '.' : 'q'; });
  g.p.face({g.id(1, 1), g.id(1, 2), g.id(2, 2), g.id(2, 1)});
  const QuadSubmesh s = checked(g.p);
  EXPECT_EQ(s.counts.cut_edges, 4u);
  EXPECT_EQ(s.counts.cut_vertices, 4u);
  const Summary k = expect_partition(s, {g.id(1, 1), g.id(2, 1), g.id(1, 2), g.id(2, 2)}, 20u, 28u, 9u);
  EXPECT_EQ(s.adjacency.component_count, 2u);
  // The flipped cell keeps its corner order.
  EXPECT_EQ(s.quad_face.back(), 8u);
}

// Two 2x2 sheets touching at one vertex, the middle of the first's top side and of the second's
// bottom side: 4 quads there in two fans. Each copy keeps 3 edges (D = 0); both sheets are structured
// disks: 4 + 4 schematic vertices, 4 + 4 edges, two 2x2 patches.
TEST(Submesh, BowTieVertex) {
  Grid a = Grid::make(2, 2, [](int, int) { return 'q'; });
  Poly p = a.p;
  // Second sheet: vertex (x, y) is 9 + y * 3 + x, but its (1,0) is the first's (1,2).
  auto b = [&](int x, int y) {
    return x == 1 && y == 0 ? a.id(1, 2) : static_cast<std::uint32_t>(9 + y * 3 + x);
  };
  p.nv = 18;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) p.face({b(i, j), b(i + 1, j), b(i + 1, j + 1), b(i, j + 1)});
  const QuadSubmesh s = checked(p);
  EXPECT_EQ(s.counts.cut_vertices, 1u);
  const Summary k = summarize(s);
  EXPECT_TRUE(k.extraordinary.empty());
  EXPECT_EQ(k.kinds, (std::vector<ComponentKind>{ComponentKind::kDisk, ComponentKind::kDisk}));
  EXPECT_EQ(k.x, 8u);
  EXPECT_EQ(k.e, 8u);
  EXPECT_EQ(k.sizes, (Sizes{{2, 2}, {2, 2}}));
  // The unused (1,0) of the second sheet's numbering (vertex 10) is kept unreferenced.
  EXPECT_EQ(s.adjacency.valence[10], 0u);
}

// A Möbius band of 4 quads: no face is flipped, so it is cut exactly where the corner orders disagree,
// the one edge (b0, a0) both end quads traverse from b0 to a0. What is left is a 1x4 strip.
TEST(Submesh, MobiusBandIsCutWhereItsOrientationsDisagree) {
  Poly p;
  p.nv = 8;  // a_i = i, b_i = 4 + i, closed with a_4 = b_0 and b_4 = a_0
  for (std::uint32_t i = 0; i < 3; ++i) p.face({i, i + 1, 5 + i, 4 + i});
  p.face({3, 4, 0, 7});
  const QuadSubmesh s = checked(p);
  EXPECT_EQ(s.counts.cut_edges, 1u);
  EXPECT_EQ(s.counts.cut_vertices, 2u);
  const Summary k = summarize(s);
  EXPECT_EQ(k.kinds, std::vector<ComponentKind>{ComponentKind::kDisk});
  EXPECT_EQ(k.sizes, (Sizes{{1, 4}}));
}

// A mesh of triangles only (a tetrahedron): no quad, one region whose four vertices are all interior.
TEST(Submesh, TrianglesOnly) {
  Poly p;
  p.nv = 4;
  p.face({0, 2, 1});
  p.face({0, 1, 3});
  p.face({1, 2, 3});
  p.face({2, 0, 3});
  const QuadSubmesh s = checked(p);
  EXPECT_EQ(s.mesh.face_count(), 0u);
  EXPECT_EQ(s.mesh.vertex_count(), 0u);
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_EQ(s.regions[0].interior.size(), 4u);
  EXPECT_TRUE(s.regions[0].loops.empty());
  EXPECT_TRUE(partition_motorcycle(s.adjacency).components.empty());
}

// A tube: a band of triangles between two bands of quads touches both their loops.
TEST(Submesh, TriangleBandTouchesTwoLoops) {
  const QuadSubmesh s = checked(testing::triangle_band(5));
  EXPECT_EQ(s.loop_halfedge.size(), 4u);
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_EQ(s.regions[0].loops.size(), 2u);
  EXPECT_EQ(summarize(s).kinds,
            (std::vector<ComponentKind>{ComponentKind::kAnnulus, ComponentKind::kAnnulus}));
}

// A closed surface with a fin on one edge: the surface's two faces there meet again at the same two
// copies with opposite directions, so the quad submesh glues them back (the fin comes off, the surface
// stays closed: a cube's 8 corners, 12 edges, 6 patches) and the fin is a unit patch.
TEST(Submesh, FinOnAClosedSurfaceComesOff) {
  Poly p;
  p.nv = 10;
  const std::vector<std::array<std::uint32_t, 4>> cube = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                          {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (const auto& q : cube) p.face({q[0], q[1], q[2], q[3]});
  p.face({0, 1, 8, 9});  // on edge 0-1, which the cube's faces 0 and 2 share
  const QuadSubmesh s = checked(p);
  EXPECT_EQ(s.counts.cut_edges, 1u);
  const Summary k = summarize(s);
  EXPECT_EQ(k.x, 8u + 4u);
  EXPECT_EQ(k.e, 12u + 4u);
  EXPECT_EQ(k.patches, 7u);
  EXPECT_EQ(s.adjacency.component_count, 2u);
}

// Shapes that would make a quadratic rule hang (ctest's timeout catches that; nothing is timed here):
// an edge with 50,000 quads, a vertex with 25,000 quads between 25,000 triangles, a 50,000-gon.
TEST(Submesh, HostileShapesCostTheirSize) {
  const std::uint32_t n = 50000;
  Poly book;
  book.nv = 2 + 2 * n;
  for (std::uint32_t i = 0; i < n; ++i) book.face({0, 1, 2 + 2 * i, 3 + 2 * i});
  const QuadSubmesh b = submesh(book);
  EXPECT_EQ(b.counts.cut_edges, 1u);
  EXPECT_EQ(b.counts.cut_vertices, 2u);
  EXPECT_EQ(b.counts.extra_copies, 2 * (n - 1));
  EXPECT_EQ(b.adjacency.component_count, n);
  const Poly fan = testing::alternating_fan(n);
  const QuadSubmesh f = checked(fan);
  EXPECT_EQ(f.regions.size(), n / 2);
  EXPECT_EQ(f.counts.cut_vertices, 1u);
  EXPECT_EQ(f.counts.extra_copies, n / 2 - 1);
  const Poly ngon = testing::ngon_with_a_quad(n);
  const QuadSubmesh g = checked(ngon);
  ASSERT_EQ(g.regions.size(), 1u);
  EXPECT_EQ(g.regions[0].interior.size(), n - 2);
  EXPECT_EQ(g.regions[0].loops.size(), 1u);
}

// ---- Errors: only what is not a mesh, in build_adjacency's words.

TEST(Submesh, RefusesWhatIsNotAMesh) {
  auto code_of = [](const Poly& p) {
    try {
      (void)quad_submesh(p.offsets, p.corners, p.nv);
    } catch (const Error& e) {
      return std::make_pair(e.code(), std::string(e.what()));
    }
    return std::make_pair(ErrorCode::kInternal, std::string("accepted"));
  };
  Poly range;
  range.nv = 4;
  range.face({0, 1, 2});
  range.face({0, 2, 7});
  EXPECT_EQ(code_of(range), std::make_pair(ErrorCode::kBadIndex,
                                           std::string("face 1: vertex index 7 out of range (4 vertices)")));
  Poly repeat;
  repeat.nv = 4;
  repeat.face({0, 1, 2, 1});
  EXPECT_EQ(code_of(repeat),
            std::make_pair(ErrorCode::kDegenerateFace, std::string("face 0: vertex 1 appears twice")));
  Poly two;
  two.nv = 4;
  two.face({0, 1, 2});
  two.face({2, 3});
  EXPECT_EQ(code_of(two).first, ErrorCode::kDegenerateFace);
  EXPECT_NE(code_of(two).second.find("face 1"), std::string::npos);
  Poly bad_offsets = range;
  bad_offsets.offsets = {0, 3, 2, 6};
  EXPECT_EQ(code_of(bad_offsets).first, ErrorCode::kInternal);
  // The quad-only messages match build_adjacency's on the same quads.
  Poly quad_range;
  quad_range.nv = 4;
  quad_range.face({0, 1, 2, 9});
  try {
    (void)build_adjacency(quad_range.corners, quad_range.nv);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(code_of(quad_range), std::make_pair(e.code(), std::string(e.what())));
  }
}

// ---- Properties.

// What must not change under renumbering: the canonical codes of the quad submesh's partition, the
// counts, and each region's face degrees, interior size and number of loops.
struct Shape {
  std::uint64_t fingerprint = 0;
  std::vector<std::tuple<std::vector<std::uint32_t>, std::size_t, std::size_t>> regions;
  std::array<std::uint32_t, 6> counts{};
  std::size_t loops = 0, vertices = 0;
  bool operator==(const Shape&) const = default;
};

Shape shape(const Poly& p, const QuadSubmesh& s) {
  Shape out;
  const Partition part = partition_motorcycle(s.adjacency);
  out.fingerprint = topology_fingerprint(canonicalize(s.mesh, s.adjacency, part));
  for (const auto& r : s.regions) {
    std::vector<std::uint32_t> degrees;
    for (std::uint32_t f : r.faces) degrees.push_back(p.degree(f));
    std::sort(degrees.begin(), degrees.end());
    out.regions.emplace_back(degrees, r.interior.size(), r.loops.size());
  }
  std::sort(out.regions.begin(), out.regions.end());
  const PolygonCounts& c = s.counts;
  out.counts = {c.quads, c.triangles, c.ngons, c.cut_edges, c.cut_vertices, c.extra_copies};
  out.loops = s.loop_halfedge.size();
  out.vertices = s.vertex_original.size();
  return out;
}

void expect_invariant(const Poly& p, int rounds = 3) {
  const Shape base = shape(p, submesh(p));
  for (int round = 0; round < rounds; ++round) {
    const Poly q = testing::shuffled(p, 1234 + round);
    const QuadSubmesh s = checked(q);
    EXPECT_TRUE(shape(q, s) == base) << "round " << round;
  }
}

TEST(Submesh, RenumberingGivesAnIsomorphicResult) {
  for (const auto& [name, p] : testing::hand_polygon_cases()) {
    SCOPED_TRACE(name);
    expect_invariant(p);
  }
}

TEST(Submesh, AllQuadManifoldMeshComesOutAsItself) {
  const Poly p = Grid::make(6, 4, [](int, int) { return 'q'; }).p;
  const QuadSubmesh s = submesh(p);
  EXPECT_EQ(s.mesh.quads, p.corners);
  EXPECT_EQ(s.mesh.vertex_count(), p.nv);
  EXPECT_TRUE(s.regions.empty());
  EXPECT_EQ(s.counts.cut_vertices + s.counts.cut_edges + s.counts.extra_copies, 0u);
}

// ---- The shared meshes, read by testing::read_faces (faces of any degree).

// Independent counts of what rule 1 cuts: edges with 3+ faces, and 2-face edges traversed one way.
std::pair<std::uint32_t, std::uint32_t> nonmanifold_and_flipped(const Poly& p) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<bool>> edges;  // (lo, hi) -> lo first?
  for (std::uint32_t f = 0; f < p.face_count(); ++f)
    for (std::uint32_t c = p.offsets[f]; c < p.offsets[f + 1]; ++c) {
      const std::uint32_t a = p.corners[c], b = p.corners[c + 1 == p.offsets[f + 1] ? p.offsets[f] : c + 1];
      edges[{std::min(a, b), std::max(a, b)}].push_back(a < b);
    }
  std::uint32_t many = 0, same = 0;
  for (const auto& [e, dirs] : edges) {
    if (dirs.size() >= 3) ++many;
    if (dirs.size() == 2 && dirs[0] == dirs[1]) ++same;
  }
  return {many, same};
}

// Independent counts of a polygon mesh: connected components (faces joined across edges that exactly
// two faces share) and boundary edges (edges of one face).
std::pair<std::uint32_t, std::uint32_t> components_and_boundary(const Poly& p,
                                                                const std::vector<std::uint32_t>& corners) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> faces_of;
  for (std::uint32_t f = 0; f < p.face_count(); ++f)
    for (std::uint32_t c = p.offsets[f]; c < p.offsets[f + 1]; ++c) {
      const std::uint32_t a = corners[c], b = corners[c + 1 == p.offsets[f + 1] ? p.offsets[f] : c + 1];
      faces_of[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  std::vector<std::uint32_t> parent(p.face_count());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  std::uint32_t boundary = 0, components = p.face_count();
  for (const auto& [e, fs] : faces_of) {
    if (fs.size() == 1) ++boundary;
    if (fs.size() != 2 || find(fs[0]) == find(fs[1])) continue;
    parent[find(fs[0])] = find(fs[1]);
    --components;
  }
  return {components, boundary};
}

long num(const testing::ManifestRow& row, const char* key) { return row.num(key); }
template <class T>
long num(T x) {
  return static_cast<long>(x);
}

TEST(Submesh, EverySharedMeshGivesAValidQuadSubmesh) {
  QSP_NEEDS_SHARED();
  int files = 0, rows = 0;
  for (const fs::path& dir : testing::shared_mesh_dirs()) {
    const auto manifest = testing::read_manifest(dir / "MANIFEST.tsv");
    rows += static_cast<int>(manifest.size());
    for (const fs::path& path : testing::mesh_files_in(dir)) {
      SCOPED_TRACE(path.string());
      const auto row = manifest.find(path.filename().string());
      ASSERT_NE(row, manifest.end());
      const Poly p = testing::read_faces(path);
      ++files;
      EXPECT_EQ(num(p.nv), num(row->second, "V"));
      EXPECT_EQ(num(p.face_count()), num(row->second, "F"));
      if (num(row->second, "degenerate_faces") > 0) {
        try {
          (void)submesh(p);
          ADD_FAILURE() << "a face repeating a vertex was accepted";
        } catch (const Error& e) {
          EXPECT_EQ(e.code(), ErrorCode::kDegenerateFace) << e.what();
        }
        continue;
      }
      const QuadSubmesh s = checked(p);
      EXPECT_EQ(num(s.counts.quads), num(row->second, "quads"));
      EXPECT_EQ(num(s.counts.triangles), num(row->second, "tris"));
      EXPECT_EQ(num(s.counts.ngons), num(row->second, "other_polys"));
      const auto [many, same] = nonmanifold_and_flipped(p);
      EXPECT_EQ(num(many), num(row->second, "nonmanifold_edges"));
      EXPECT_EQ(s.counts.cut_edges, many + same);
      const bool manifold = num(row->second, "nonmanifold_edges") == 0 &&
                            num(row->second, "nonmanifold_vertices") == 0 &&
                            num(row->second, "flipped_edges") == 0;
      if (manifold) {
        EXPECT_EQ(s.counts.cut_edges, 0u);
        const ManifoldCut cut = cut_manifold(p.offsets, p.corners, p.nv);
        EXPECT_EQ(cut.cut_vertices, 0u);
        const auto [components, boundary] = components_and_boundary(p, cut.corners);
        EXPECT_EQ(num(components), num(row->second, "components"));
        EXPECT_EQ(num(boundary), num(row->second, "boundary_edges"));
      }
      if (manifold && row->second.col.at("all_quad") == "True") {
        EXPECT_EQ(s.mesh.quads, p.corners);  // a valid quad mesh is its own quad submesh
        EXPECT_EQ(num(s.adjacency.component_count), num(row->second, "components"));
        EXPECT_EQ(num(extraordinary_vertices(s.adjacency).size()), num(row->second, "extraordinary"));
      }
      (void)summarize(s);  // partition() on the quad submesh, every component validated
    }
  }
  EXPECT_EQ(files, rows);
}

TEST(Submesh, SharedMeshesRenumberedGiveAnIsomorphicResult) {
  QSP_NEEDS_SHARED();
  int renumbered = 0;
  for (const fs::path& path : testing::shared_meshes()) {
    SCOPED_TRACE(path.string());
    const Poly p = testing::read_faces(path);
    if (p.face_count() > 40000) continue;  // the larger ones add time, not cases
    try {
      (void)cut_manifold(p.offsets, p.corners, p.nv);
    } catch (const Error&) {
      continue;  // not a mesh (checked above)
    }
    expect_invariant(p, 1);
    ++renumbered;
  }
  EXPECT_GT(renumbered, 80);
}

}  // namespace
}  // namespace qsp
