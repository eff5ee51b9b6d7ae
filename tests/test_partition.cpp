// Motorcycle graph and schematic partition: hand-checked cases, paper bounds, invariance, corpus.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "support/mesh_gen.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

struct Counts {
  std::uint32_t x = 0, e = 0, patches = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> sizes;  // sorted (min, max)
};

Counts counts(const Partition& p) {
  Counts c;
  for (const auto& part : p.components) {
    if (part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus) {
      ++c.patches;
      continue;
    }
    const Schematic& s = part.schematic;
    c.x += s.vertex_count;
    c.e += s.edge_count();
    c.patches += s.patch_count();
    for (std::uint32_t f = 0; f < s.face_count(); ++f)
      if (!s.face_hole[f]) {
        const PatchSize z = patch_size(s, f);
        c.sizes.emplace_back(std::min(z.a, z.b), std::max(z.a, z.b));
      }
  }
  std::sort(c.sizes.begin(), c.sizes.end());
  return c;
}

Partition checked_partition(const QuadMesh& m, const Adjacency& adj) {
  Partition p = partition_motorcycle(adj);
  for (const auto& part : p.components) {
    const std::string why = validate(part, &adj);
    EXPECT_EQ(why, "") << "component " << part.component;
  }
  (void)m;
  return p;
}

QuadMesh load(const fs::path& path) { return read_mesh_file(path.string()); }

TEST(KnownAnswers, SharedHandWorkedCases) {
  const fs::path dir = fs::path(QSP_SHARED_DIR) / "known-answers";
  if (!fs::exists(dir)) GTEST_SKIP() << "no " << dir;
  struct Case {
    const char* file;
    std::uint32_t extraordinary, x, e;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> sizes;
  };
  const std::vector<Case> cases = {
      {"right_hand_rule.obj", 2, 12, 16, {{2, 4}, {2, 4}, {2, 6}, {2, 6}, {4, 4}}},
      {"head_on_vertex.obj", 2, 10, 13, {{2, 2}, {2, 4}, {2, 4}, {2, 4}}},
      {"stop_point_blocks.obj", 5, 20, 28, {{1, 2}, {1, 2}, {1, 3}, {2, 2}, {2, 2}, {2, 2}, {2, 3}, {2, 3}, {2, 3}}},
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

}  // namespace
}  // namespace qsp
