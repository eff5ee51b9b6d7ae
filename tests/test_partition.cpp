// Motorcycle graph and schematic partition: hand-checked cases, paper bounds, invariance, corpus.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "layout_grid.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "stencil.h"
#include "support/corpus.h"
#include "support/load.h"
#include "support/mesh_gen.h"
#include "support/schematic_counts.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

using Counts = testing::SchematicCounts;
constexpr auto counts = testing::schematic_counts;

Partition checked_partition(const QuadMesh& m, const Adjacency& adj) {
  Partition p = partition_motorcycle(adj);
  for (const auto& part : p.components) {
    const std::string why = validate(part, &adj);
    EXPECT_EQ(why, "") << "component " << part.component;
  }
  (void)m;
  return p;
}

using testing::load;

// The hand-worked cases of ../shared/known-answers, copied into testdata/ so they run in every clone.
TEST(KnownAnswers, HandWorkedCases) {
  const fs::path dir = fs::path(QSP_TESTDATA_DIR) / "known-answers";
  struct Case {
    const char* file;
    std::uint32_t extraordinary, x, e;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> sizes;
  };
  const std::vector<Case> cases = {
      {"right_hand_rule.obj", 2, 12, 16, {{2, 4}, {2, 4}, {2, 6}, {2, 6}, {4, 4}}},
      {"head_on_vertex.obj", 2, 10, 13, {{2, 2}, {2, 4}, {2, 4}, {2, 4}}},
      {"stop_point_blocks.obj",
       5,
       20,
       28,
       {{1, 2}, {1, 2}, {1, 3}, {2, 2}, {2, 2}, {2, 2}, {2, 3}, {2, 3}, {2, 3}}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    const QuadMesh m = load(dir / c.file);
    const Adjacency adj = build_adjacency(m);
    EXPECT_EQ(extraordinary_vertices(adj).size(), c.extraordinary);
    const Counts k = counts(checked_partition(m, adj));
    EXPECT_EQ(k.x, c.x);
    EXPECT_EQ(k.e, c.e);
    EXPECT_EQ(k.sizes, c.sizes);
  }
}

// Worked by hand (README, "Motorcycle graph"): the L's concave corner sends one particle down and one
// left, both to the boundary. In the staircase the particle going south from (2,4) and the one going
// west from (4,2) reach (2,2) together at step 2; the face between their tracks is the cell north-east
// of (2,2), whose own half-edge into (2,2) comes from the north, so the south-going one continues.
TEST(Partition, HandCheckedPolyominoes) {
  struct Case {
    QuadMesh mesh;
    std::uint32_t x, e;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> sizes;
  };
  const std::vector<Case> cases = {
      {testing::polyomino({"###...", "###...", "###...", "######", "######", "######"}),
       8,
       10,
       {{3, 3}, {3, 3}, {3, 3}}},
      {testing::polyomino({"##....", "##....", "####..", "####..", "######", "######"}),
       12,
       16,
       {{2, 2}, {2, 2}, {2, 2}, {2, 2}, {2, 4}}},
      {testing::grid(5, 3), 4, 4, {{3, 5}}},
  };
  for (const auto& c : cases) {
    const Adjacency adj = build_adjacency(c.mesh);
    const Counts k = counts(checked_partition(c.mesh, adj));
    EXPECT_EQ(k.x, c.x);
    EXPECT_EQ(k.e, c.e);
    EXPECT_EQ(k.sizes, c.sizes);
  }
  // The staircase's continuing particle reaches the boundary at (2,0): the edge (2,0)-(2,1) is traced.
  const QuadMesh stairs = cases[1].mesh;
  const Adjacency adj = build_adjacency(stairs);
  bool found = false;
  for (std::uint32_t h : trace_motorcycles(adj, extraordinary_vertices(adj)).traced) {
    const float* p = &stairs.positions[3 * adj.origin[h]];
    const float* q = &stairs.positions[3 * adj.dest(h)];
    if (p[0] == 2 && q[0] == 2 && std::min(p[1], q[1]) == 0) found = true;
  }
  EXPECT_TRUE(found);
}

TEST(Partition, StructuredComponentsAreOnePatch) {
  struct Case {
    QuadMesh mesh;
    ComponentKind kind;
    std::uint32_t a, b;
  };
  const std::vector<Case> cases = {{testing::periodic(9, 6, true, 2), ComponentKind::kTorus, 9, 6},
                                   {testing::periodic(7, 4, true, 0), ComponentKind::kTorus, 7, 4},
                                   {testing::periodic(12, 3, false, 0), ComponentKind::kAnnulus, 12, 3},
                                   {testing::grid(4, 4), ComponentKind::kDisk, 0, 0}};
  for (const auto& c : cases) {
    const Adjacency adj = build_adjacency(c.mesh);
    const Partition p = checked_partition(c.mesh, adj);
    ASSERT_EQ(p.components.size(), 1u);
    EXPECT_EQ(p.components[0].kind, c.kind);
    if (c.a) {
      EXPECT_EQ(p.components[0].a * p.components[0].b, c.a * c.b);
    }
    EXPECT_EQ(counts(p).patches, 1u);
  }
}

TEST(Partition, RefinedCubeHasSixSquarePatches) {
  for (int n : {1, 2, 3, 4, 7, 8}) {
    SCOPED_TRACE(n);
    const QuadMesh m = testing::cube(n);
    const Adjacency adj = build_adjacency(m);
    const Counts k = counts(checked_partition(m, adj));
    EXPECT_EQ(k.x, 8u);
    EXPECT_EQ(k.e, 12u);
    EXPECT_EQ(k.patches, 6u);
    for (auto s : k.sizes) EXPECT_EQ(s, std::make_pair(std::uint32_t(n), std::uint32_t(n)));
  }
}

using testing::corpus;

// Traced edges as sorted pairs of vertex ids mapped through `to_original`.
std::vector<std::pair<std::uint32_t, std::uint32_t>> traced_pairs(
    const Adjacency& adj, const std::vector<std::uint32_t>* to_original) {
  const MotorcycleGraph g = trace_motorcycles(adj, extraordinary_vertices(adj));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (std::uint32_t h : g.traced) {
    std::uint32_t u = adj.origin[h], v = adj.dest(h);
    if (to_original) u = (*to_original)[u], v = (*to_original)[v];
    out.emplace_back(std::min(u, v), std::max(u, v));
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Bounds of Theorem 1, generalised to components with boundary (README, "Bounds"): with P particles,
// n_b extraordinary boundary vertices and c boundary corners,
//   V <= n + c + P,   E <= 2P + n_b + c,   4 * patches <= 3P + n_b + c;
// on closed components P = 4n - 4chi and these are exactly 5n - 4chi, 8n - 8chi, 3n - 3chi.
void check_bounds(const Adjacency& adj, const Partition& p) {
  const auto info = component_info(adj);
  std::vector<std::int64_t> particles(adj.component_count, 0), nb(adj.component_count, 0),
      corners(adj.component_count, 0);
  for (std::uint32_t v = 0; v < adj.vertex_count; ++v) {
    if (adj.valence[v] == 0) continue;
    const std::uint32_t h = adj.vertex_halfedge[v];
    const std::uint32_t c = adj.face_component[adj.is_exterior(h) ? adj.face(adj.twin[h]) : adj.face(h)];
    if (adj.extraordinary(v)) {
      particles[c] += adj.boundary[v] ? adj.valence[v] - 2 : adj.valence[v];
      nb[c] += adj.boundary[v];
    } else if (adj.boundary[v] && adj.valence[v] == 2) {
      ++corners[c];
    }
  }
  for (const auto& part : p.components) {
    const std::uint32_t c = part.component;
    // Lemma 1 per component.
    EXPECT_EQ(info[c].deficiency_sum, 4 * info[c].euler()) << "Lemma 1, component " << c;
    if (part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus) {
      EXPECT_EQ(info[c].euler(), 0);
      continue;
    }
    const Schematic& s = part.schematic;
    const std::int64_t P = particles[c], n = info[c].extraordinary;
    EXPECT_LE(s.vertex_count, n + corners[c] + P);
    EXPECT_LE(s.edge_count(), 2 * P + nb[c] + corners[c]);
    EXPECT_LE(4 * s.patch_count(), 3 * P + nb[c] + corners[c]);
    if (info[c].boundary_edges == 0) {
      EXPECT_EQ(P, 4 * n - 4 * info[c].euler());
      EXPECT_LE(s.vertex_count, 5 * n - 4 * info[c].euler());
      EXPECT_LE(s.edge_count(), 8 * n - 8 * info[c].euler());
      EXPECT_LE(s.patch_count(), 3 * n - 3 * info[c].euler());
    }
  }
}

TEST(Corpus, EveryValidMeshPartitionsIntoGridsWithinBounds) {
  int partitioned = 0, refused = 0;
  for (const auto& path : corpus()) {
    SCOPED_TRACE(path.string());
    QuadMesh m;
    Adjacency adj;
    if (!testing::read_valid(path, m, &adj)) {
      ++refused;
      continue;
    }
    Partition p;
    ASSERT_NO_THROW(p = checked_partition(m, adj));
    check_bounds(adj, p);
    // Invariance: a shuffled copy traces exactly the same edges of the original.
    std::vector<std::uint32_t> to_original;
    const QuadMesh s = testing::shuffled(m, 7, &to_original);
    const Adjacency sadj = build_adjacency(s);
    EXPECT_EQ(traced_pairs(adj, nullptr), traced_pairs(sadj, &to_original));
    ++partitioned;
  }
  std::printf("partitioned %d meshes, refused %d\n", partitioned, refused);
  EXPECT_EQ(partitioned, testing::expected_valid_count(corpus()));
}

// Patch coding order over every mesh: a permutation of the layout's vertices, each
// stencil naming only earlier ones, every parallelogram stencil (w, s, sw) a real cell of the mesh with
// the point as its fourth corner, and the explicit se/ss/sww/ssw (which patch order takes as given,
// annulus and torus included) mesh neighbours continuing that frame.
TEST(Corpus, PatchOrderStencilsAreCellsOfTheMesh) {
  int checked = 0;
  std::size_t extended = 0;  // frames with se or ss, over the whole corpus
  for (const auto& path : corpus()) {
    SCOPED_TRACE(path.string());
    QuadMesh m;
    Adjacency adj;
    if (!testing::read_valid(path, m, &adj)) continue;
    for (const ComponentPartition& comp : partition_motorcycle(adj).components) {
      Numbering numbering;
      const GridLayout layout = grid_layout(comp, numbering);
      const ComponentStencils patch = component_stencils(comp, layout, numbering, CodingOrder::kPatch);
      const std::uint32_t n = layout.vertex_count;
      ASSERT_EQ(patch.stencil.size(), n);
      std::vector<std::uint32_t> coding = patch.coding;
      if (coding.empty()) {  // annulus / torus: already row by row
        ASSERT_TRUE(comp.kind == ComponentKind::kAnnulus || comp.kind == ComponentKind::kTorus);
        for (std::uint32_t v = 0; v < n; ++v) coding.push_back(v);
        // Patch order reads se/ss/sww/ssw from every stencil: a grid point two rows up and two
        // columns in must have all four.
        if (comp.a >= 4 && n >= 3 * comp.a) {
          const Stencil& t = patch.stencil[2 * comp.a + 2];
          EXPECT_TRUE(t.se != kInvalid && t.ss != kInvalid && t.sww != kInvalid && t.ssw != kInvalid);
        }
      }
      std::vector<std::uint32_t> sorted = coding;
      std::sort(sorted.begin(), sorted.end());
      for (std::uint32_t v = 0; v < n; ++v) ASSERT_EQ(sorted[v], v) << "not a permutation";
      // Cells as (corner, next, opposite, previous) in layout numbering, and the mesh edges.
      std::set<std::array<std::uint32_t, 4>> cells;
      std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
      for (std::size_t q = 0; q < layout.quads.size(); q += 4)
        for (std::uint32_t r = 0; r < 4; ++r) {
          const std::uint32_t c0 = layout.quads[q + r], c1 = layout.quads[q + (r + 1) % 4];
          cells.insert({c0, c1, layout.quads[q + (r + 2) % 4], layout.quads[q + (r + 3) % 4]});
          edges.insert({std::min(c0, c1), std::max(c0, c1)});
        }
      auto edge = [&](std::uint32_t x, std::uint32_t y) {
        return edges.count({std::min(x, y), std::max(x, y)}) > 0;
      };
      for (std::uint32_t k = 0; k < n; ++k) {
        const Stencil& t = patch.stencil[k];
        for (std::uint32_t j : t.vertex_fields())
          ASSERT_TRUE(j == kInvalid || j < k) << "stencil of " << k << " refers forward";
        if (t.w == kInvalid || t.s == kInvalid || t.sw == kInvalid) continue;
        const std::uint32_t p = coding[k], w = coding[t.w], s = coding[t.s], sw = coding[t.sw];
        // p, then s, sw, w around one cell (either orientation).
        EXPECT_TRUE(cells.count({p, s, sw, w}) || cells.count({p, w, sw, s})) << "vertex " << p;
        // The explicit farther neighbours continue that frame: se and ss next to s, sww next to sw,
        // ssw next to sw and ss.
        EXPECT_TRUE(t.se == kInvalid || edge(coding[t.se], s)) << "se of " << p;
        EXPECT_TRUE(t.ss == kInvalid || edge(coding[t.ss], s)) << "ss of " << p;
        EXPECT_TRUE(t.sww == kInvalid || edge(coding[t.sww], sw)) << "sww of " << p;
        EXPECT_TRUE(t.ssw == kInvalid || (edge(coding[t.ssw], sw) && edge(coding[t.ssw], coding[t.ss])))
            << "ssw of " << p;
        extended += t.se != kInvalid || t.ss != kInvalid;
      }
    }
    ++checked;
  }
  EXPECT_GT(checked, 0);
  EXPECT_GT(extended, 0u);
}

// check_stencils reads the stencil as words under a mask built from vertex_fields(): every vertex field
// is checked (a forward one in any field is refused), and no other field (a large distance is not a
// vertex).
TEST(Stencils, CheckRefusesAForwardReferenceInEveryVertexField) {
  std::vector<Stencil> ok(3);
  ok[1].w = 0;
  ok[2].w = 1, ok[2].s = 0, ok[2].far_dist = 1000, ok[2].e_dist = 1000, ok[2].xden = 1000;
  EXPECT_NO_THROW(check_stencils(ok, 3));
  for (std::size_t k = 0; k < Stencil{}.vertex_fields().size(); ++k) {
    for (const std::uint32_t bad : {2u, 3u, 1000u}) {
      std::vector<Stencil> st = ok;
      *st[2].vertex_fields()[k] = bad;
      try {
        check_stencils(st, 3);
        ADD_FAILURE() << "field " << k << " = " << bad << " at position 2 was not refused";
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::kInternal);
      }
    }
  }
  EXPECT_THROW(check_stencils(ok, 4), Error);
}

}  // namespace
}  // namespace qsp
