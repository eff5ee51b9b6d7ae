// Region codes and glue (qsp/regions.h): every polygon mesh made here and every shared mesh comes back
// from its codes face by face and corner by corner under the numbering the codes define; renumbered
// copies give identical codes; inconsistent codes are refused with a format error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/partition.h"
#include "qsp/regions.h"
#include "qsp/submesh.h"
#include "support/corpus.h"
#include "support/polygon.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::Grid;
using testing::Poly;

// A polygon mesh taken through the pipeline the codec will run: quad submesh, motorcycle partition,
// canonical form, region codes; then the layout the decoder rebuilds (grid_layout per component, offset,
// then the unreferenced vertices) and its adjacency.
struct Coded {
  QuadSubmesh submesh;
  CanonicalRegions regions;
  std::vector<std::uint32_t> layout_quads;
  Adjacency layout_adjacency;
};

Coded code(const Poly& p) {
  Coded c;
  c.submesh = quad_submesh(p.offsets, p.corners, p.nv, p.positions);
  const Partition part = partition_motorcycle(c.submesh.adjacency);
  c.regions = canonical_regions(p.offsets, p.corners, p.nv, p.positions, c.submesh,
                                canonicalize(c.submesh.mesh, c.submesh.adjacency, part));
  std::uint32_t base = 0;
  for (const CanonicalComponent& cc : c.regions.quads.components) {
    const GridLayout g = grid_layout(cc.part);
    for (std::uint32_t v : g.quads) c.layout_quads.push_back(v + base);
    base += g.vertex_count;
  }
  base += static_cast<std::uint32_t>(c.regions.quads.unreferenced.size());
  EXPECT_EQ(base, c.regions.codes.layout_vertices);
  c.layout_adjacency = build_adjacency(c.layout_quads, base);
  return c;
}

PolygonFaces rebuild(const Coded& c, const RegionCodes& codes) {
  return rebuild_polygons(c.layout_quads, c.layout_adjacency, codes);
}

// Each face as a cyclic sequence of vertex ids, rotated to start at its smallest, sorted: two polygon
// meshes on the same vertices have the same faces (corner order kept) exactly when these are equal.
std::vector<std::vector<std::uint32_t>> face_multiset(const std::vector<std::uint32_t>& offsets,
                                                      const std::vector<std::uint32_t>& corners,
                                                      const std::vector<std::uint32_t>& vertex_name) {
  std::vector<std::vector<std::uint32_t>> faces;
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f) {
    std::vector<std::uint32_t> face;
    for (std::uint32_t c = offsets[f]; c < offsets[f + 1]; ++c) face.push_back(vertex_name[corners[c]]);
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
    faces.push_back(std::move(face));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// The rebuilt mesh has exactly the input's faces on the input's vertices, checked here without the
// maps canonical_regions returns: each ref is named by the input vertex whose position the codec stores
// for it (layout vertices through the canonical layout, interior ones by interior_original); the refs
// rebuild_polygons merges into one output vertex must name one input vertex, distinct output vertices
// distinct ones, every input vertex named; then the faces, renamed, must be the input's as cyclic
// sequences. Then the maps a --keep-order decode would use are checked against the same output.
void expect_round_trip(const Poly& p, const Coded& c) {
  const CanonicalRegions& m = c.regions;
  const PolygonFaces out = rebuild(c, m.codes);
  ASSERT_EQ(out.vertex_count, p.nv);
  ASSERT_EQ(out.face_offsets.size(), p.offsets.size());
  std::vector<std::uint32_t> ref_input;
  for (const CanonicalComponent& cc : m.quads.components)
    for (std::uint32_t v : cc.map.vertex) ref_input.push_back(c.submesh.vertex_original[v]);
  for (std::uint32_t v : m.quads.unreferenced) ref_input.push_back(c.submesh.vertex_original[v]);
  ASSERT_EQ(ref_input.size(), m.codes.layout_vertices);
  ref_input.insert(ref_input.end(), m.interior_original.begin(), m.interior_original.end());
  ASSERT_EQ(ref_input.size(), out.ref_vertex.size());
  std::vector<std::uint32_t> name(p.nv, kInvalid), named_by(p.nv, kInvalid);  // output -> input, reverse
  for (std::size_t x = 0; x < ref_input.size(); ++x) {
    const std::uint32_t o = out.ref_vertex[x], v = ref_input[x];
    ASSERT_LT(o, p.nv);
    ASSERT_LT(v, p.nv);
    if (name[o] == kInvalid) name[o] = v;
    ASSERT_EQ(name[o], v) << "output vertex " << o << " merges refs of two input vertices";
    if (named_by[v] == kInvalid) named_by[v] = o;
    ASSERT_EQ(named_by[v], o) << "input vertex " << v << " is two output vertices";
  }
  ASSERT_EQ(std::count(name.begin(), name.end(), kInvalid), 0) << "an output vertex names no input vertex";
  std::vector<std::uint32_t> identity(p.nv);
  std::iota(identity.begin(), identity.end(), 0u);
  EXPECT_TRUE(face_multiset(out.face_offsets, out.corners, name) ==
              face_multiset(p.offsets, p.corners, identity))
      << "the rebuilt faces are not the input's";

  // The keep-order maps: output vertex, face and first corner of every input face.
  ASSERT_EQ(m.vertex, named_by);
  ASSERT_EQ(m.face.size(), p.face_count());
  std::vector<int> fhit(p.face_count(), 0);
  for (std::uint32_t f = 0; f < p.face_count(); ++f) {
    ASSERT_LT(m.face[f], p.face_count());
    ++fhit[m.face[f]];
  }
  EXPECT_EQ(std::count(fhit.begin(), fhit.end(), 1), p.face_count());
  for (std::uint32_t f = 0; f < p.face_count(); ++f) {
    const std::uint32_t g = m.face[f], d = p.degree(f);
    ASSERT_EQ(out.face_offsets[g + 1] - out.face_offsets[g], d) << "face " << f;
    for (std::uint32_t i = 0; i < d; ++i)
      ASSERT_EQ(out.corners[out.face_offsets[g] + i],
                m.vertex[p.corners[p.offsets[f] + (i + m.rotation[f]) % d]])
          << "face " << f << " corner " << i;
  }
}

// Distinct positions on a lattice, in a shuffled order (so positions decide no tie by accident).
Poly with_positions(Poly p, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint32_t> slot(p.nv);
  std::iota(slot.begin(), slot.end(), 0u);
  std::shuffle(slot.begin(), slot.end(), rng);
  p.positions.resize(3 * std::size_t{p.nv});
  for (std::uint32_t v = 0; v < p.nv; ++v) {
    p.positions[3 * v] = static_cast<float>(slot[v] % 7);
    p.positions[3 * v + 1] = static_cast<float>(slot[v] / 7 % 7);
    p.positions[3 * v + 2] = static_cast<float>(slot[v] / 49);
  }
  return p;
}

// What must not change under renumbering: the quad layout and its codes, the region codes and glue.
void expect_same_codes(const Coded& a, const Coded& b, const std::string& what) {
  EXPECT_TRUE(a.regions.codes == b.regions.codes) << what;
  EXPECT_EQ(a.layout_quads, b.layout_quads) << what;
  ASSERT_EQ(a.regions.quads.components.size(), b.regions.quads.components.size()) << what;
  for (std::size_t i = 0; i < a.regions.quads.components.size(); ++i)
    EXPECT_TRUE(a.regions.quads.components[i].code == b.regions.quads.components[i].code) << what;
}

void expect_canonical(const Poly& p, const std::string& name, int rounds = 3) {
  SCOPED_TRACE(name);
  const Coded base = code(p);
  expect_round_trip(p, base);
  for (int round = 0; round < rounds; ++round) {
    const Poly q = testing::shuffled(p, 77 + round);
    const Coded c = code(q);
    expect_round_trip(q, c);
    expect_same_codes(base, c, name + ", round " + std::to_string(round));
  }
}

// ---- Hand-made cases.

TEST(Regions, HandMadeCasesRoundTripAndAreCanonical) {
  for (const auto& [name, p] : testing::hand_polygon_cases()) expect_canonical(p, name);
}

TEST(Regions, HandMadeCasesWithPositionsRoundTripAndAreCanonical) {
  for (const auto& [name, p] : testing::hand_polygon_cases()) expect_canonical(with_positions(p, 5), name);
}

// A quad mesh codes nothing: no region, no glue, and the layout is the codec's as it is today.
TEST(Regions, QuadMeshHasNoRegionsAndNoGlue) {
  const Poly p = Grid::make(4, 3, [](int, int) { return 'q'; }).p;
  const Coded c = code(p);
  EXPECT_TRUE(c.regions.codes.regions.empty());
  EXPECT_EQ(c.regions.codes.glue.size(), 0u);
  EXPECT_EQ(c.regions.codes.interior_vertices, 0u);
  expect_round_trip(p, c);
}

// Two triangles in a square hole: the first entered through a hole edge, the second through the
// diagonal (the one edge the first pushes); each third corner is the hole vertex next to its known
// corners, named by kFollow or kClose: one symbol per face, no value.
TEST(Regions, TwoTrianglesInASquareHoleCostOneSymbolEach) {
  Grid g = Grid::make(3, 3, [](int i, int j) { return i == 1 && j == 1 ? '.' : 'q'; });
  g.p.face({g.id(1, 1), g.id(2, 1), g.id(2, 2)});
  g.p.face({g.id(1, 1), g.id(2, 2), g.id(1, 2)});
  const Poly p = with_positions(g.p, 3);
  const Coded c = code(p);
  ASSERT_EQ(c.regions.codes.regions.size(), 1u);
  const RegionCode& r = c.regions.codes.regions[0];
  EXPECT_EQ(r.start, RegionStart::kEdge);
  EXPECT_EQ(r.degrees, (std::vector<std::uint32_t>{3, 3}));
  ASSERT_EQ(r.corners.size(), 2u);
  for (CornerSymbol x : r.corners) EXPECT_TRUE(x == CornerSymbol::kFollow || x == CornerSymbol::kClose);
  EXPECT_TRUE(r.values.empty());
  EXPECT_EQ(std::count(r.open.begin(), r.open.end(), 1), 1);
  EXPECT_TRUE(c.regions.codes.glue.empty());
  expect_round_trip(p, c);
}

// A pole: n triangles around a new vertex in an n-edge hole. One kNew; every other corner is on the hole
// next to the gate; no explicit reference.
TEST(Regions, TriangleFanPoleNeedsNoReference) {
  for (const auto& [name, p] : testing::hand_polygon_cases()) {
    if (name != "uv_sphere_poles") continue;
    const Coded c = code(with_positions(p, 9));
    ASSERT_EQ(c.regions.codes.regions.size(), 2u);
    for (const RegionCode& r : c.regions.codes.regions) {
      EXPECT_EQ(r.start, RegionStart::kEdge);
      EXPECT_EQ(r.degrees, std::vector<std::uint32_t>(6, 3));
      EXPECT_EQ(std::count(r.corners.begin(), r.corners.end(), CornerSymbol::kNew), 1);
      EXPECT_TRUE(r.values.empty());
    }
    EXPECT_EQ(c.regions.codes.interior_vertices, 2u);
    EXPECT_EQ(c.regions.codes.glue.size(), 0u);
  }
}

Poly hand_case(const std::string& name) {
  for (auto& [n, p] : testing::hand_polygon_cases())
    if (n == name) return p;
  ADD_FAILURE() << "no hand case " << name;
  return {};
}

// Glue group sizes, sorted.
std::vector<std::uint32_t> group_sizes(const RegionCodes& codes) {
  std::vector<std::uint32_t> sizes;
  for (std::size_t g = 0; g + 1 < codes.glue_offsets.size(); ++g)
    sizes.push_back(codes.glue_offsets[g + 1] - codes.glue_offsets[g]);
  std::sort(sizes.begin(), sizes.end());
  return sizes;
}

std::uint32_t count_symbol(const RegionCode& r, CornerSymbol s) {
  return static_cast<std::uint32_t>(std::count(r.corners.begin(), r.corners.end(), s));
}

// A 2x2 hole of a 4x4 quad grid filled by eight triangles, six of them around grid vertex (2, 2).
// Entered through a hole edge; every triangle after the first through a gate, so one coded corner
// each; the centre created once (kNew), never named again by value (it stays on top of the open
// half-edges); no glue. The hole's 8 vertices are the grid's, so 24 layout vertices and one interior.
TEST(Regions, TriangleRegionWithAnInteriorVertex) {
  const Poly p = hand_case("triangle_block_with_interior_vertex");
  const Coded c = code(p);
  ASSERT_EQ(c.regions.codes.regions.size(), 1u);
  const RegionCode& r = c.regions.codes.regions[0];
  EXPECT_EQ(r.start, RegionStart::kEdge);
  EXPECT_EQ(r.degrees, std::vector<std::uint32_t>(8, 3));
  EXPECT_EQ(r.corners.size(), 8u);  // one coded corner per gated triangle
  EXPECT_EQ(count_symbol(r, CornerSymbol::kNew), 1u);
  EXPECT_EQ(count_symbol(r, CornerSymbol::kInterior), 0u);
  EXPECT_EQ(r.values.size(), 2 * count_symbol(r, CornerSymbol::kBoundary));
  EXPECT_EQ(c.regions.codes.interior_vertices, 1u);
  EXPECT_EQ(c.regions.codes.layout_vertices, 24u);  // 25 grid vertices but the centre
  ASSERT_EQ(c.regions.interior_original.size(), 1u);
  EXPECT_EQ(c.regions.interior_original[0], 12u);  // (2, 2)
  EXPECT_TRUE(c.regions.codes.glue.empty());
  expect_round_trip(p, c);
}

// The n-gon region: a triangle, a pentagon and three hexagons around grid vertex (2, 2) with four more
// interior vertices, in a 2x2 hole. Degrees in traversal order are a rotation of the ring (3 5 6 6 6 or
// with the triangle elsewhere); five interior vertices, each created once; no glue.
TEST(Regions, NgonRegion) {
  const Poly p = hand_case("ngon_region_with_interior");
  const Coded c = code(p);
  ASSERT_EQ(c.regions.codes.regions.size(), 1u);
  const RegionCode& r = c.regions.codes.regions[0];
  std::vector<std::uint32_t> degrees = r.degrees;
  std::sort(degrees.begin(), degrees.end());
  EXPECT_EQ(degrees, (std::vector<std::uint32_t>{3, 5, 6, 6, 6}));
  EXPECT_EQ(count_symbol(r, CornerSymbol::kNew), 5u);
  EXPECT_EQ(c.regions.codes.interior_vertices, 5u);
  // Corners coded: every face but the first is entered through a gate (two corners known), the first
  // through the hole edge (two known too): 1 + 3 + 4 + 4 + 4 for degrees 3 5 6 6 6.
  EXPECT_EQ(r.corners.size(), 16u);
  EXPECT_TRUE(c.regions.codes.glue.empty());
  expect_round_trip(p, c);
}

// Grid vertex (2, 2) of a 4x4 grid whose cells (1, 1) and (2, 2) are triangle pairs: its quads
// (cells (1, 2) and (2, 1)) form two quad fans, so it has two layout copies, glued back by one group.
TEST(Regions, VertexCutApartByTrianglesIsGlued) {
  const Poly p = hand_case("vertex_cut_apart_by_triangles");
  const Coded c = code(p);
  EXPECT_EQ(c.regions.codes.regions.size(), 2u);
  ASSERT_EQ(group_sizes(c.regions.codes), std::vector<std::uint32_t>{2});
  EXPECT_LT(c.regions.codes.glue[1], c.regions.codes.layout_vertices);  // both copies are quad vertices
  EXPECT_EQ(c.regions.codes.layout_vertices, p.nv + 1);
  EXPECT_EQ(c.regions.codes.interior_vertices, 0u);
  expect_round_trip(p, c);
}

// A fin quad on the middle edge (1, 0)-(1, 1) of a 2x2 grid: the edge has three quads and is cut. At
// (1, 0) the three quads are three fans (three copies); at (1, 1) the grid's four quads stay one fan
// and the fin another (two copies). No non-quad face, so no region: only glue, groups of 2 and 3.
TEST(Regions, NonManifoldEdgeIsGlued) {
  const Poly p = hand_case("nonmanifold_edge_three_quads");
  const Coded c = code(p);
  EXPECT_TRUE(c.regions.codes.regions.empty());
  EXPECT_EQ(group_sizes(c.regions.codes), (std::vector<std::uint32_t>{2, 3}));
  EXPECT_EQ(c.regions.codes.layout_vertices, p.nv + 3);
  expect_round_trip(p, c);
}

// The clockwise centre quad of a 3x3 grid: its four edges run the same way as its neighbours' and are
// cut, so it comes off whole; its four corners get two copies each, glued back by four groups of two.
TEST(Regions, MisorientedFaceIsGlued) {
  const Poly p = hand_case("misoriented_face");
  const Coded c = code(p);
  EXPECT_TRUE(c.regions.codes.regions.empty());
  EXPECT_EQ(group_sizes(c.regions.codes), std::vector<std::uint32_t>(4, 2));
  EXPECT_EQ(c.regions.quads.components.size(), 2u);
  expect_round_trip(p, c);
}

// No quad at all: one free region per component, every vertex interior.
TEST(Regions, TriangleMeshIsFreeRegions) {
  Poly p = Grid::make(4, 3, [](int, int) { return 't'; }).p;
  const std::uint32_t nv = p.nv;
  p.nv += 4;  // and a tetrahedron beside it
  p.face({nv, nv + 2, nv + 1});
  p.face({nv, nv + 1, nv + 3});
  p.face({nv + 1, nv + 2, nv + 3});
  p.face({nv + 2, nv, nv + 3});
  for (const Poly& q : {p, with_positions(p, 4)}) {
    const Coded c = code(q);
    ASSERT_EQ(c.regions.codes.regions.size(), 2u);
    for (const RegionCode& r : c.regions.codes.regions) EXPECT_EQ(r.start, RegionStart::kFree);
    EXPECT_EQ(c.regions.codes.layout_vertices, 0u);
    EXPECT_EQ(c.regions.codes.interior_vertices, p.nv);
    expect_canonical(q, "triangles and a tetrahedron");
  }
}

// Vertices in no face stay layout vertices (after the components), not glued to anything.
TEST(Regions, UnreferencedVerticesAreKept) {
  Grid g = Grid::make(3, 2, [](int i, int j) { return i == 1 && j == 0 ? 't' : 'q'; });
  g.p.nv += 3;
  const Coded c = code(with_positions(g.p, 1));
  EXPECT_EQ(c.regions.quads.unreferenced.size(), 3u);
  expect_canonical(with_positions(g.p, 1), "unreferenced");
  expect_canonical(g.p, "unreferenced, no positions");
}

// Several regions at one vertex copy, regions touching two loops, a vertex cut by triangles: glue.
TEST(Regions, GlueMergesTheCopiesOfCutVertices) {
  for (const auto& [name, p] : testing::hand_polygon_cases()) {
    const Coded c = code(p);
    std::uint32_t copies = 0;
    for (std::size_t g = 0; g + 1 < c.regions.codes.glue_offsets.size(); ++g)
      copies += c.regions.codes.glue_offsets[g + 1] - c.regions.codes.glue_offsets[g] - 1;
    EXPECT_EQ(copies, c.submesh.counts.extra_copies) << name;
  }
}

// Two quad components equal in topology and positions (a quad sheet and its copy at the same place),
// each with a triangle attached differently: which comes first is decided by the regions, so every
// renumbering gives the same codes.
TEST(Regions, TiedComponentsAreOrderedByTheirRegions) {
  Poly p;
  Grid a = Grid::make(2, 1, [](int, int) { return 'q'; });
  p = a.p;
  const std::uint32_t n = p.nv;
  p.nv = 2 * n + 2;
  for (int i = 0; i < 2; ++i)  // the copy
    p.face({n + a.id(i, 0), n + a.id(i + 1, 0), n + a.id(i + 1, 1), n + a.id(i, 1)});
  p.face({a.id(0, 1), a.id(1, 1), 2 * n});              // a triangle on the first's top left
  p.face({n + a.id(2, 0), n + a.id(2, 1), 2 * n + 1});  // and on the copy's right side
  p.positions.resize(3 * std::size_t{p.nv});
  for (std::uint32_t v = 0; v < n; ++v)
    for (std::uint32_t k = 0; k < 2; ++k)
      p.positions[3 * v + k] = p.positions[3 * (n + v) + k] = static_cast<float>(k == 0 ? v % 3 : v / 3);
  p.positions[3 * (2 * n) + 2] = 1;
  p.positions[3 * (2 * n + 1) + 2] = 2;
  expect_canonical(p, "tied components", 6);
}

// ---- Hostile codes: every inconsistency is a format error, found in time linear in the codes.

// A mesh whose codes use every symbol kind and glue: an n-gon region with interior vertices, triangle
// fans, a block of triangles with interior vertices, a cut vertex and a triangle mesh beside.
Poly rich_mesh() {
  Poly p;
  for (const auto& [name, q] : testing::hand_polygon_cases()) {
    if (name != "ngon_region_with_interior" && name != "vertex_cut_apart_by_triangles" &&
        name != "checkerboard" && name != "tetrahedron" && name != "uv_sphere_poles" &&
        name != "triangle_block_4x4")
      continue;
    for (std::uint32_t c : q.corners) p.corners.push_back(c + p.nv);
    for (std::size_t f = 1; f < q.offsets.size(); ++f)
      p.offsets.push_back(static_cast<std::uint32_t>(p.corners.size() - q.corners.size() + q.offsets[f]));
    p.nv += q.nv;
  }
  return with_positions(p, 11);
}

ErrorCode refusal(const Coded& c, const RegionCodes& codes) {
  try {
    (void)rebuild(c, codes);
  } catch (const Error& e) {
    return e.code();
  }
  return ErrorCode::kInternal;  // stands for "accepted"
}

TEST(Regions, RichMeshUsesEverySymbol) {
  const Poly p = rich_mesh();
  const Coded c = code(p);
  expect_round_trip(p, c);
  std::map<CornerSymbol, int> seen;
  std::map<RegionStart, int> starts;
  for (const RegionCode& r : c.regions.codes.regions) {
    ++starts[r.start];
    for (CornerSymbol s : r.corners) ++seen[s];
  }
  EXPECT_EQ(seen.size(), 5u);
  EXPECT_EQ(starts.size(), 2u);
  EXPECT_GT(c.regions.codes.glue.size(), 0u);
}

TEST(Regions, TruncatedStreamsAreRefused) {
  const Coded c = code(rich_mesh());
  int tried = 0;
  for (std::size_t r = 0; r < c.regions.codes.regions.size(); ++r)
    for (int stream = 0; stream < 4; ++stream) {
      RegionCodes codes = c.regions.codes;
      RegionCode& x = codes.regions[r];
      switch (stream) {
        case 0:
          if (x.degrees.empty()) continue;
          x.degrees.pop_back();
          break;
        case 1:
          if (x.corners.empty()) continue;
          if (x.corners.back() == CornerSymbol::kNew) --codes.interior_vertices;
          x.corners.pop_back();
          break;
        case 2:
          if (x.values.empty()) continue;
          x.values.pop_back();
          break;
        default:
          if (x.open.empty()) continue;
          x.open.pop_back();
      }
      ++tried;
      EXPECT_EQ(refusal(c, codes), ErrorCode::kFormat) << "region " << r << " stream " << stream;
    }
  EXPECT_GT(tried, 20);
  RegionCodes fewer = c.regions.codes;
  fewer.regions.pop_back();
  EXPECT_EQ(refusal(c, fewer), ErrorCode::kFormat);  // its new vertices are still declared
}

TEST(Regions, OutOfRangeReferencesAreRefused) {
  const Coded c = code(rich_mesh());
  auto mutated = [&](auto change) {
    RegionCodes codes = c.regions.codes;
    change(codes);
    return refusal(c, codes);
  };
  auto first_region = [&](RegionStart s) {
    for (std::size_t r = 0; r < c.regions.codes.regions.size(); ++r)
      if (c.regions.codes.regions[r].start == s) return r;
    return std::size_t{0};
  };
  const std::size_t edge = first_region(RegionStart::kEdge);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[edge].loop = 1000; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[edge].position = 1u << 30; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[edge].degrees[0] = 4; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[edge].degrees[0] = 2; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[edge].degrees[0] = 1u << 30; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[edge].open[0] = 2; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[edge].start = static_cast<RegionStart>(7); }),
            ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { ++x.interior_vertices; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.interior_vertices = 0xFFFFFFFFu; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([&](RegionCodes& x) { std::swap(x.regions[0], x.regions[1]); }), ErrorCode::kFormat);
  // Every value of every region pushed out of range.
  for (std::size_t r = 0; r < c.regions.codes.regions.size(); ++r)
    for (std::size_t i = 0; i < c.regions.codes.regions[r].values.size(); ++i)
      EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[r].values[i] = 1u << 30; }), ErrorCode::kFormat)
          << "region " << r << " value " << i;
  // A free region's first vertex claimed by a hole vertex is not a free start any more.
  const std::size_t free = first_region(RegionStart::kFree);
  EXPECT_EQ(mutated([&](RegionCodes& x) { x.regions[free].loop = 1; }), ErrorCode::kFormat);
}

TEST(Regions, InconsistentGlueIsRefused) {
  const Coded c = code(rich_mesh());
  const RegionCodes& good = c.regions.codes;
  ASSERT_GE(good.glue_offsets.size(), 3u);
  auto mutated = [&](auto change) {
    RegionCodes codes = good;
    change(codes);
    return refusal(c, codes);
  };
  // A group of one: drop the second member of the first group.
  EXPECT_EQ(mutated([](RegionCodes& x) {
              const std::uint32_t b = x.glue_offsets[0], e = x.glue_offsets[1];
              x.glue.erase(x.glue.begin() + b + 1, x.glue.begin() + e);
              for (std::size_t g = 1; g < x.glue_offsets.size(); ++g) x.glue_offsets[g] -= e - b - 1;
            }),
            ErrorCode::kFormat);
  EXPECT_EQ(mutated([](RegionCodes& x) { x.glue.back() = x.layout_vertices + x.interior_vertices; }),
            ErrorCode::kFormat);
  EXPECT_EQ(mutated([](RegionCodes& x) { std::swap(x.glue[0], x.glue[1]); }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([](RegionCodes& x) { x.glue[x.glue_offsets[1]] = x.glue[0]; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([](RegionCodes& x) { x.glue_offsets.back() += 1; }), ErrorCode::kFormat);
  EXPECT_EQ(mutated([](RegionCodes& x) { x.glue_offsets.assign(1, 1); }), ErrorCode::kFormat);
  // A group ending past the glue (offsets not increasing, the last one right): read nothing past it.
  EXPECT_EQ(mutated([](RegionCodes& x) {
              const auto n = static_cast<std::uint32_t>(x.glue.size());
              x.glue_offsets = {0, n + 1000, n};
            }),
            ErrorCode::kFormat);
}

// Glue well-formed in itself that merges two corners of one quad: the face would repeat a vertex.
TEST(Regions, GlueMergingTwoCornersOfAFaceIsRefused) {
  const Coded c = code(Grid::make(2, 1, [](int, int) { return 'q'; }).p);
  RegionCodes codes = c.regions.codes;
  ASSERT_TRUE(codes.glue.empty());
  codes.glue = {std::min(c.layout_quads[0], c.layout_quads[1]),
                std::max(c.layout_quads[0], c.layout_quads[1])};
  codes.glue_offsets = {0, 2};
  try {
    (void)rebuild(c, codes);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(e.what()).find("repeats vertex"), std::string::npos) << e.what();
  }
}

// Random single changes anywhere in the codes: a format error or a valid polygon mesh, never anything
// else (the fuzz target of the codec section will do this on bytes).
TEST(Regions, RandomChangesAreRefusedOrGiveAMesh) {
  const Coded c = code(rich_mesh());
  std::mt19937 rng(2024);
  int refused = 0, accepted = 0;
  for (int round = 0; round < 5000; ++round) {
    RegionCodes codes = c.regions.codes;
    RegionCode& r = codes.regions[rng() % codes.regions.size()];
    const std::uint32_t small = rng() % 4, big = rng();
    const std::uint32_t x = rng() % 2 ? small : big;
    // A symbol inserted or removed anywhere in a stream, so everything after it is read out of step.
    auto shift = [&](auto& stream, auto inserted) {
      const std::size_t at = stream.empty() ? 0 : rng() % stream.size();
      if (rng() % 2 || stream.empty())
        stream.insert(stream.begin() + static_cast<std::ptrdiff_t>(at), inserted);
      else
        stream.erase(stream.begin() + static_cast<std::ptrdiff_t>(at));
    };
    switch (rng() % 10) {
      case 6:
        shift(r.degrees, 3 + small);
        break;
      case 7:
        shift(r.corners, static_cast<CornerSymbol>(small));
        break;
      case 8:
        shift(r.values, x);
        break;
      case 9:
        shift(r.open, static_cast<std::uint8_t>(small & 1));
        break;
      case 0:
        if (!r.degrees.empty()) r.degrees[rng() % r.degrees.size()] = 3 + small;
        break;
      case 1:
        if (!r.corners.empty()) r.corners[rng() % r.corners.size()] = static_cast<CornerSymbol>(rng() % 6);
        break;
      case 2:
        if (!r.values.empty()) r.values[rng() % r.values.size()] = x;
        break;
      case 3:
        if (!r.open.empty()) r.open[rng() % r.open.size()] ^= 1;
        break;
      case 4:
        r.position = x;
        break;
      default:
        if (!codes.glue.empty()) codes.glue[rng() % codes.glue.size()] = x % 64;
    }
    try {
      const PolygonFaces out = rebuild(c, codes);
      ++accepted;
      // What rebuild_polygons promises of anything it accepts: faces of degree 3 or more, on its
      // vertices, none repeating a vertex.
      for (std::size_t f = 0; f + 1 < out.face_offsets.size(); ++f) {
        ASSERT_GE(out.face_offsets[f + 1] - out.face_offsets[f], 3u);
        std::vector<std::uint32_t> face(out.corners.begin() + out.face_offsets[f],
                                        out.corners.begin() + out.face_offsets[f + 1]);
        for (std::uint32_t v : face) ASSERT_LT(v, out.vertex_count);
        std::sort(face.begin(), face.end());
        ASSERT_TRUE(std::adjacent_find(face.begin(), face.end()) == face.end()) << "face " << f;
      }
    } catch (const Error& e) {
      ASSERT_EQ(e.code(), ErrorCode::kFormat) << e.what();
      ++refused;
    }
  }
  EXPECT_GT(refused, 1000);
  EXPECT_GT(accepted, 10);
}

// Large hostile shapes cost their size (ctest's timeout would catch a quadratic coder): a 50,000-valence
// fan of alternating quads and triangles, a 50,000-gon, a 100,000-triangle strip without positions.
TEST(Regions, HostileShapesCostTheirSize) {
  const std::uint32_t n = 50000;
  const Poly fan = testing::alternating_fan(n);
  expect_round_trip(fan, code(fan));
  const Poly ngon = testing::ngon_with_a_quad(n);
  expect_round_trip(ngon, code(ngon));
  const Poly strip = Grid::make(2 * n / 2, 1, [](int, int) { return 't'; }).p;
  expect_round_trip(strip, code(strip));
}

// ---- Shared meshes.

// Whether a corpus file's manifest row (shared meshes only) says a face repeats a vertex: not a mesh.
bool not_a_mesh(const fs::path& path) {
  static std::map<fs::path, std::map<std::string, testing::ManifestRow>> manifests;
  const fs::path tsv = path.parent_path() / "MANIFEST.tsv";
  if (!fs::exists(tsv)) return false;
  auto it = manifests.find(tsv);
  if (it == manifests.end()) it = manifests.emplace(tsv, testing::read_manifest(tsv)).first;
  const auto row = it->second.find(path.filename().string());
  return row != it->second.end() && row->second.num("degenerate_faces") > 0;
}

// Every corpus mesh (testdata/ and the shared meshes with osd_shapes/, non-quad and non-manifold ones
// included), with and without positions; refused exactly where its manifest says it is not a mesh.
TEST(Regions, EveryCorpusMeshRoundTrips) {
  int meshes = 0;
  for (const fs::path& path : testing::corpus()) {
    SCOPED_TRACE(path.string());
    const Poly p = testing::read_faces(path);
    const bool cut = testing::cuttable(p);
    EXPECT_EQ(cut, !not_a_mesh(path));
    if (!cut) continue;
    expect_round_trip(p, code(p));
    const Poly q = with_positions(p, 21);
    expect_round_trip(q, code(q));
    ++meshes;
  }
  EXPECT_GT(meshes, testing::shared_present() ? 130 : 20);
}

TEST(Regions, CorpusMeshesRenumberedGiveTheSameCodes) {
  int renumbered = 0;
  for (const fs::path& path : testing::corpus()) {
    const Poly p = testing::read_faces(path);
    if (p.face_count() > 40000 || !testing::cuttable(p)) continue;  // the larger ones add time, not cases
    expect_canonical(p, path.filename().string(), 1);
    ++renumbered;
  }
  EXPECT_GT(renumbered, testing::shared_present() ? 100 : 20);
}

// ---- What the codes cost: symbols per non-quad face and their empirical entropy.

struct Entropy {
  std::map<std::uint64_t, double> counts;
  void add(std::uint64_t x) { counts[x] += 1; }
  double bits() const {
    double n = 0, h = 0;
    for (const auto& [k, c] : counts) n += c;
    for (const auto& [k, c] : counts) h -= c * std::log2(c / n);
    return h;
  }
};

// Elias-gamma length of x >= 1.
double gamma_bits(std::uint64_t x) { return 2 * std::floor(std::log2(static_cast<double>(x))) + 1; }

struct Cost {
  std::uint64_t faces = 0, symbols = 0;
  double bits = 0;
  std::map<std::string, double> parts;
};

// Entropy of each stream (corner symbols in two contexts: a face's last coded corner or not), explicit
// values and starts by Elias gamma, glue by gamma of sizes and gaps.
Cost cost(const RegionCodes& codes) {
  Cost out;
  Entropy degrees, symbols[2], open, kinds;
  double values = 0, starts = 0, glue = 0;
  std::uint32_t loop = 0, position = 0;
  for (const RegionCode& r : codes.regions) {
    out.faces += r.degrees.size();
    out.symbols += 1 + r.degrees.size() + r.corners.size() + r.values.size() + r.open.size();
    kinds.add(static_cast<std::uint64_t>(r.start));
    if (r.start != RegionStart::kFree) {
      starts += gamma_bits(r.loop - loop + 1);
      starts += gamma_bits((r.loop == loop ? r.position - position : r.position) + 1);
      loop = r.loop;
      position = r.position;
    }
    std::size_t ci = 0;
    for (std::size_t f = 0; f < r.degrees.size(); ++f) {
      degrees.add(r.degrees[f]);
      const std::size_t coded = r.degrees[f] - (f == 0 && r.start != RegionStart::kEdge ? 1 : 2);
      for (std::size_t i = 0; i < coded; ++i, ++ci)
        symbols[i + 1 == coded].add(static_cast<int>(r.corners[ci]));
    }
    for (std::size_t i = 0; i < r.values.size(); ++i) values += gamma_bits(r.values[i] + 1);
    for (std::uint8_t o : r.open) open.add(o);
  }
  for (std::size_t g = 0; g + 1 < codes.glue_offsets.size(); ++g) {
    glue += gamma_bits(codes.glue_offsets[g + 1] - codes.glue_offsets[g] - 1);
    std::uint32_t prev = g == 0 ? 0 : codes.glue[codes.glue_offsets[g - 1]];
    for (std::uint32_t i = codes.glue_offsets[g]; i < codes.glue_offsets[g + 1]; ++i) {
      glue += gamma_bits(codes.glue[i] - prev + 1);
      prev = codes.glue[i];
    }
  }
  out.symbols += codes.glue.size() + codes.glue_offsets.size();
  out.parts = {{"degrees", degrees.bits()},
               {"corners", symbols[0].bits() + symbols[1].bits()},
               {"values", values},
               {"open", open.bits()},
               {"starts", starts + kinds.bits()},
               {"glue", glue}};
  for (const auto& [k, b] : out.parts) out.bits += b;
  return out;
}

TEST(Regions, SymbolCostsOfQuadDominantMeshes) {
  QSP_NEEDS_SHARED();
  const std::vector<std::string> names = {"osd_catmark_bishop.obj", "pmp_suzanne.obj",
                                          "keenan_spot_control_mesh.obj", "osd_catmark_nonquads.obj"};
  for (const std::string& name : names) {
    const Poly p = testing::read_faces(testing::shared_dir() / "meshes" / name);
    const Coded c = code(p);
    const Cost k = cost(c.regions.codes);
    ASSERT_GT(k.faces, 0u) << name;
    std::printf("%-30s %6llu non-quad faces  %5.2f symbols/face  %5.2f bits/face  (", name.c_str(),
                static_cast<unsigned long long>(k.faces), static_cast<double>(k.symbols) / k.faces,
                k.bits / k.faces);
    for (const auto& [part, b] : k.parts) std::printf(" %s %.2f", part.c_str(), b / k.faces);
    std::printf(" )\n");
    // The targets (Draco's -preserve_polygons: 5.5-5.8 bits per face); the others are reported:
    // with 10-20 non-quad faces their cost is mostly starts and glue, and the estimate is rough.
    if (name == "osd_catmark_bishop.obj" || name == "pmp_suzanne.obj") {
      EXPECT_LT(k.bits / k.faces, 5.5) << name;
    }
  }
}

}  // namespace
}  // namespace qsp
