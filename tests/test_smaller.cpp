// Smaller partitions (§7) and highway meshes (§8): validity of every mode on every mesh, canonical
// invariance, hand-checked sizes, and the optimum formulas on generated highway meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "codec_sections.h"
#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "qsp/smaller.h"
#include "support/cli.h"
#include "support/corpus.h"
#include "support/highway.h"
#include "support/mesh_gen.h"

namespace qsp {
namespace {

constexpr PartitionMode kModes[] = {PartitionMode::kMotorcycle, PartitionMode::kGreedy,
                                    PartitionMode::kMerge};

void expect_valid(const Partition& p, const Adjacency& adj, const char* what) {
  for (const auto& part : p.components)
    EXPECT_EQ(validate(part, &adj), "") << what << ", component " << part.component;
}

std::vector<TopologyCode> codes(const QuadMesh& m, const Adjacency& adj, const Partition& p) {
  std::vector<TopologyCode> out;
  for (const auto& c : canonicalize(m, adj, p).components) out.push_back(c.code);
  return out;
}

// Decodability: the mode's canonical codes go through the topology coder and back, are rebuilt by
// partition_from_code and laid out; the mesh that comes out is isomorphic to the input (equal
// motorcycle-graph codes), whatever partition the codes were made from.
void check_round_trip(const QuadMesh& m, const Adjacency& adj, const std::vector<TopologyCode>& mode_codes) {
  std::uint64_t edges = 0, max_length = 0;
  for (const auto& c : mode_codes) {
    edges += c.edge_length.size();
    for (auto l : c.edge_length) max_length = std::max<std::uint64_t>(max_length, l);
  }
  const std::vector<TopologyCode> back = decode_topology(encode_topology(mode_codes), 0, mode_codes.size(),
                                                         edges, std::max<std::uint64_t>(max_length, 1));
  ASSERT_EQ(back, mode_codes);
  QuadMesh rebuilt;
  for (const auto& c : back) {
    const GridLayout g = grid_layout(partition_from_code(c));
    const auto base = static_cast<std::uint32_t>(rebuilt.vertex_count());
    rebuilt.positions.resize(rebuilt.positions.size() + 3ull * g.vertex_count, 0.0f);
    for (std::uint32_t v : g.quads) rebuilt.quads.push_back(base + v);
  }
  const Adjacency radj = build_adjacency(rebuilt);
  EXPECT_EQ(codes(rebuilt, radj, partition_motorcycle(radj)), codes(m, adj, partition_motorcycle(adj)));
}

// The building blocks on their own: greedy's cut set needs no fallback, and merging never grows.
void check_pieces(const Adjacency& adj) {
  const Partition motorcycle = partition_motorcycle(adj);
  const PartitionSize zm = partition_size(motorcycle);
  Partition greedy;
  ASSERT_NO_THROW(greedy = partition_from_cuts(adj, greedy_cuts(adj)));
  expect_valid(greedy, adj, "greedy without merging");
  const std::vector<std::uint32_t> traced = trace_motorcycles(adj, extraordinary_vertices(adj)).traced;
  const std::vector<std::uint32_t> merged = merge_cuts(adj, traced);
  EXPECT_LE(merged.size(), traced.size());
  Partition merge;
  ASSERT_NO_THROW(merge = partition_from_cuts(adj, merged));
  const PartitionSize zg = partition_size(greedy), zmerge = partition_size(merge);
  EXPECT_LE(zmerge.edges, zm.edges);
  EXPECT_LE(zmerge.vertices, zm.vertices);
  EXPECT_LE(zmerge.patches, zm.patches);
  // The mode functions add the merge pass to greedy: never larger than greedy alone.
  EXPECT_LE(partition_size(partition(adj, PartitionMode::kGreedy)).edges, zg.edges);
  EXPECT_EQ(partition_size(partition(adj, PartitionMode::kMerge)).edges, zmerge.edges);
}

TEST(PartitionModes, NamesRoundTrip) {
  for (PartitionMode m : kModes) {
    PartitionMode back = PartitionMode::kMotorcycle;
    EXPECT_TRUE(parse_partition_mode(partition_mode_name(m), back));
    EXPECT_EQ(back, m);
  }
  PartitionMode x = PartitionMode::kGreedy;
  EXPECT_FALSE(parse_partition_mode("all", x));
  EXPECT_FALSE(parse_partition_mode("", x));
  EXPECT_EQ(x, PartitionMode::kGreedy);
}

TEST(PartitionModes, MotorcycleModeIsTheMotorcycleGraph) {
  const QuadMesh m = testing::polyomino({"##....", "##....", "####..", "####..", "######", "######"});
  const Adjacency adj = build_adjacency(m);
  EXPECT_EQ(codes(m, adj, partition(adj, PartitionMode::kMotorcycle)),
            codes(m, adj, partition_motorcycle(adj)));
}

// Worked by hand. Refined cube: the motorcycle graph cuts along the 12 cube edges (6 patches); greedy
// joins corners by cube edges only where a corner still needs one, leaving two interlocking n x 3n
// bands (8 vertices, 8 edges, 2 patches), and merging the six faces gets there too. L shape: the
// concave corner needs one of its two inner edges cut, giving two rectangles (7 vertices, 8 edges).
TEST(PartitionModes, HandCheckedSizes) {
  struct Case {
    QuadMesh mesh;
    PartitionMode mode;
    std::uint64_t v, e, p;
  };
  const std::vector<Case> cases = {
      {testing::cube(4), PartitionMode::kGreedy, 8, 8, 2},
      {testing::cube(4), PartitionMode::kMerge, 8, 8, 2},
      {testing::cube(3), PartitionMode::kGreedy, 8, 8, 2},
      {testing::polyomino({"###...", "###...", "###...", "######", "######", "######"}),
       PartitionMode::kGreedy, 7, 8, 2},
      {testing::polyomino({"###...", "###...", "###...", "######", "######", "######"}),
       PartitionMode::kMerge, 7, 8, 2},
      {testing::grid(5, 3), PartitionMode::kGreedy, 4, 4, 1},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(partition_mode_name(c.mode));
    const Adjacency adj = build_adjacency(c.mesh);
    const Partition p = partition(adj, c.mode);
    expect_valid(p, adj, partition_mode_name(c.mode));
    const PartitionSize z = partition_size(p);
    EXPECT_EQ(z.vertices, c.v);
    EXPECT_EQ(z.edges, c.e);
    EXPECT_EQ(z.patches, c.p);
  }
  // The cube's bands are n x 3n grids.
  const QuadMesh cube = testing::cube(4);
  const Adjacency adj = build_adjacency(cube);
  const Partition p = partition(adj, PartitionMode::kGreedy);
  const Schematic& s = p.components[0].schematic;
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    const PatchSize z = patch_size(s, f);
    EXPECT_EQ(std::min(z.a, z.b), 4u);
    EXPECT_EQ(std::max(z.a, z.b), 12u);
  }
}

TEST(PartitionModes, StructuredComponentsStayWhole) {
  QuadMesh m = testing::periodic(9, 6, true, 2);
  testing::append(m, testing::periodic(12, 3, false, 0), 20);
  testing::append(m, testing::grid(4, 3), 40);
  testing::append(m, testing::cube(3), 60);
  const Adjacency adj = build_adjacency(m);
  const Partition ref = partition_motorcycle(adj);
  for (PartitionMode mode : kModes) {
    SCOPED_TRACE(partition_mode_name(mode));
    const Partition p = partition(adj, mode);
    ASSERT_EQ(p.components.size(), ref.components.size());
    expect_valid(p, adj, partition_mode_name(mode));
    for (std::size_t c = 0; c < p.components.size(); ++c) {
      EXPECT_EQ(p.components[c].kind, ref.components[c].kind);
      if (ref.components[c].kind != ComponentKind::kUnstructured) {
        EXPECT_EQ(p.components[c].a, ref.components[c].a);
        EXPECT_EQ(p.components[c].b, ref.components[c].b);
        EXPECT_EQ(p.components[c].schematic.edge_count(), ref.components[c].schematic.edge_count());
      }
    }
  }
}

TEST(PartitionModes, EveryCorpusMeshGivesValidCanonicalPartitions) {
  int partitioned = 0;
  std::uint64_t edges[3] = {0, 0, 0};
  for (const auto& path : testing::corpus()) {
    SCOPED_TRACE(path.string());
    QuadMesh m;
    Adjacency adj;
    if (!testing::read_valid(path, m, &adj)) continue;
    check_pieces(adj);
    // Shuffled copy: renumbered vertices, reordered faces, rotated corners.
    const QuadMesh shuffled = testing::shuffled(m, 11);
    const Adjacency sadj = build_adjacency(shuffled);
    for (int k = 0; k < 3; ++k) {
      SCOPED_TRACE(partition_mode_name(kModes[k]));
      const Partition p = partition(adj, kModes[k]);
      expect_valid(p, adj, partition_mode_name(kModes[k]));
      const Partition q = partition(sadj, kModes[k]);
      expect_valid(q, sadj, "shuffled");
      const std::vector<TopologyCode> c = codes(m, adj, p);
      EXPECT_EQ(c, codes(shuffled, sadj, q)) << "not canonical";
      check_round_trip(m, adj, c);
      edges[k] += partition_size(p).edges;
    }
    ++partitioned;
  }
  std::printf("%d meshes; schematic edges in total: motorcycle %llu, greedy %llu, merge %llu\n", partitioned,
              (unsigned long long)edges[0], (unsigned long long)edges[1], (unsigned long long)edges[2]);
  EXPECT_EQ(partitioned, testing::expected_valid_count(testing::corpus()));
}

// Canonical also means: a mirror-free relabelling of a symmetric mesh (many tied canonical roots) still
// gives one code, and meshes that differ get different codes in every mode.
TEST(PartitionModes, SymmetricAndDistinctMeshes) {
  const QuadMesh cube = testing::cube(5);
  const QuadMesh l_shape = testing::polyomino({"###...", "###...", "###...", "######", "######", "######"});
  const QuadMesh stairs = testing::polyomino({"##....", "##....", "####..", "####..", "######", "######"});
  for (PartitionMode mode : kModes) {
    SCOPED_TRACE(partition_mode_name(mode));
    for (std::uint64_t seed : {1, 2, 3}) {
      const QuadMesh s = testing::shuffled(cube, seed);
      const Adjacency a1 = build_adjacency(cube), a2 = build_adjacency(s);
      EXPECT_EQ(codes(cube, a1, partition(a1, mode)), codes(s, a2, partition(a2, mode)));
    }
    const Adjacency al = build_adjacency(l_shape), as = build_adjacency(stairs);
    EXPECT_NE(codes(l_shape, al, partition(al, mode)), codes(stairs, as, partition(as, mode)));
  }
}

// §8: the optimal casing of a highway mesh has exactly the sizes the formulas give, the generator's
// meshes have the structure described (2n + 4j extraordinary vertices, boundary valence 4), and every
// mode is valid on them and never beats the optimum.
TEST(Highway, OptimalCasingMatchesFormulas) {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE(seed);
    const int n = 3 + static_cast<int>(seed % 8);
    const highway::Arrangement arr = highway::random_arrangement(seed, n, 20);
    const highway::HighwayMesh h = highway::build(arr);
    const Adjacency adj = build_adjacency(h.mesh);
    const auto info = component_info(adj);
    std::int64_t faces = 0;
    for (int s = 0; s < h.n; ++s) faces += 2 * h.length[s] - 2;
    EXPECT_EQ(std::int64_t(h.mesh.face_count()), faces - 4 * h.j);
    const std::vector<std::uint32_t> xv = extraordinary_vertices(adj);
    EXPECT_EQ(xv.size(), std::size_t(2 * h.n + 4 * h.j));
    for (std::uint32_t x : xv) {
      EXPECT_TRUE(adj.boundary[x]);
      EXPECT_EQ(adj.valence[x], 4u);
    }
    const std::vector<int> visible = highway::max_noncrossing(arr);
    const std::int64_t k = static_cast<std::int64_t>(visible.size());
    const highway::Counts opt = highway::optimal_counts(h.n, h.j, k);
    const Partition cased = partition_from_cuts(adj, highway::optimal_cuts(h, adj, visible));
    expect_valid(cased, adj, "optimal casing");
    const PartitionSize z = partition_size(cased);
    EXPECT_EQ(std::int64_t(z.vertices), opt.vertices);
    EXPECT_EQ(std::int64_t(z.edges), opt.edges);
    EXPECT_EQ(std::int64_t(z.patches), opt.patches);
    // A worse casing (no visible segment at all) costs exactly 2k vertices, 3k edges and k patches more.
    const PartitionSize worse = partition_size(partition_from_cuts(adj, highway::optimal_cuts(h, adj, {})));
    EXPECT_EQ(std::int64_t(worse.vertices), opt.vertices + 2 * k);
    EXPECT_EQ(std::int64_t(worse.edges), opt.edges + 3 * k);
    EXPECT_EQ(std::int64_t(worse.patches), opt.patches + k);
    for (PartitionMode mode : kModes) {
      SCOPED_TRACE(partition_mode_name(mode));
      const Partition p = partition(adj, mode);
      expect_valid(p, adj, partition_mode_name(mode));
      const PartitionSize m = partition_size(p);
      EXPECT_GE(std::int64_t(m.vertices), opt.vertices);
      EXPECT_GE(std::int64_t(m.edges), opt.edges);
      EXPECT_GE(std::int64_t(m.patches), opt.patches);
      if (mode != PartitionMode::kMotorcycle) {
        EXPECT_LE(2 * std::int64_t(m.edges), 3 * opt.edges) << "more than 1.5x the optimal edges";
      }
    }
  }
}

TEST(Highway, BruteForceFindsTheLargestNonCrossingSet) {
  // Segment 0 crosses 1 and 2, which are disjoint; 3 crosses nothing: the best set drops only 0.
  highway::Arrangement arr;
  arr.segments = {{{0, 0}, {10, 1}}, {{1, -3}, {2, 5}}, {{8, -3}, {7, 5}}, {{0, 10}, {10, 11}}};
  for (int s = 0; s < 4; ++s)
    for (int t = s + 1; t < 4; ++t)
      if (highway::classify(arr.segments[s], arr.segments[t]) == 1) arr.crossings.emplace_back(s, t);
  ASSERT_EQ(arr.crossings.size(), 2u);  // 0 crosses 1 and 2; 1 and 2 are disjoint
  const std::vector<int> best = highway::max_noncrossing(arr);
  EXPECT_EQ(best, (std::vector<int>{1, 2, 3}));
  // Determinism of the generator.
  const auto a = highway::random_arrangement(7, 8), b = highway::random_arrangement(7, 8);
  EXPECT_EQ(a.crossings, b.crossings);
}

// `qsp stats --partition`: one row per mode with "all", the mode named in the row and in JSON.
TEST(PartitionModes, StatsCommandPrintsEveryMode) {
  const std::string cube = testing::quote(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj");
  const auto all = testing::run_qsp("stats --partition all " + cube);
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_NE(all.out.find("|       8      12       6 |"), std::string::npos) << all.out;  // motorcycle
  EXPECT_NE(all.out.find("[greedy]"), std::string::npos) << all.out;
  EXPECT_NE(all.out.find("[merge]"), std::string::npos) << all.out;
  EXPECT_NE(all.out.find("|       8       8       2 |"), std::string::npos) << all.out;  // two n x 3n bands
  const auto json = testing::run_qsp("stats --json --partition merge " + cube);
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_NE(json.out.find("\"partition\": \"merge\""), std::string::npos) << json.out;
  EXPECT_NE(json.out.find("\"edges\": 8,"), std::string::npos) << json.out;
  EXPECT_EQ(testing::run_qsp("stats --partition smallest " + cube).exit_code, 2);
}

}  // namespace
}  // namespace qsp
