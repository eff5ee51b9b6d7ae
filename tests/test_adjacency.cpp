// build_adjacency's two-thread path (the threaded seam, CONTRIBUTING "Threads"): forced on small and
// corpus meshes, it gives the one-thread adjacency member for member and refuses what it refuses.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "../src/mesh_split.h"
#include "qsp/error.h"
#include "qsp/mesh.h"
#include "support/corpus.h"
#include "support/mesh_gen.h"

namespace qsp {
namespace {

void expect_same(const Adjacency& a, const Adjacency& b) {
  EXPECT_EQ(a.vertex_count, b.vertex_count);
  EXPECT_EQ(a.face_count, b.face_count);
  EXPECT_EQ(a.twin, b.twin);
  EXPECT_EQ(a.origin, b.origin);
  EXPECT_EQ(a.exterior_next, b.exterior_next);
  EXPECT_EQ(a.vertex_halfedge, b.vertex_halfedge);
  EXPECT_EQ(a.valence, b.valence);
  EXPECT_EQ(a.boundary, b.boundary);
  EXPECT_EQ(a.face_component, b.face_component);
  EXPECT_EQ(a.component_faces, b.component_faces);
  EXPECT_EQ(a.component_count, b.component_count);
}

TEST(Adjacency, TwoThreadsGiveTheSameAdjacency) {
  std::vector<QuadMesh> meshes{testing::cube(1),
                               testing::cube(6),
                               testing::grid(1, 1),
                               testing::grid(7, 3),
                               testing::periodic(8, 5, true, 2),
                               testing::periodic(6, 4, false, 0),
                               testing::polyomino({"###.", "#.##", "####"}),
                               testing::copies(testing::cube(2), 4, 3.0f)};
  QuadMesh mixed = testing::grid(5, 5);
  testing::append(mixed, testing::periodic(9, 3, false, 0), 10.0f);
  testing::append(mixed, testing::cube(3), 20.0f);
  mixed.positions.insert(mixed.positions.end(), {1.0f, 2.0f, 3.0f});  // an unreferenced vertex
  meshes.push_back(testing::shuffled(mixed, 5));
  meshes.push_back(std::move(mixed));
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    SCOPED_TRACE(k);
    const QuadMesh& m = meshes[k];
    const auto nv = static_cast<std::uint32_t>(m.vertex_count());
    const std::optional<Adjacency> two = detail::build_adjacency_two_threads(m.quads, nv);
    ASSERT_TRUE(two.has_value());
    expect_same(*two, build_adjacency(m, 1));
  }
  // Every valid corpus mesh up to 30000 faces (the larger ones take the two-thread path anyway).
  int n = 0;
  for (const auto& path : testing::corpus()) {
    QuadMesh m;
    if (!testing::read_valid(path, m) || m.face_count() > 30000) continue;
    SCOPED_TRACE(path.string());
    expect_same(build_adjacency(m, 2), build_adjacency(m, 1));
    ++n;
  }
  EXPECT_GT(n, 0);
}

TEST(Adjacency, TwoThreadsRefuseWhatOneThreadRefuses) {
  struct Case {
    const char* what;
    std::vector<std::uint32_t> quads;
    std::uint32_t vertices;
  };
  const std::vector<Case> cases = {
      {"index out of range", {0, 1, 2, 3, 1, 0, 4, 9}, 8},
      {"vertex twice", {0, 1, 2, 3, 1, 0, 1, 4}, 5},
      {"edge with three faces", {0, 1, 2, 3, 1, 0, 4, 5, 0, 1, 6, 7}, 8},
      {"same direction", {0, 1, 2, 3, 0, 1, 4, 5}, 6},
      {"two fans at a vertex", {0, 1, 2, 3, 0, 4, 5, 6}, 7},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    EXPECT_FALSE(detail::build_adjacency_two_threads(c.quads, c.vertices).has_value());
    std::string one, two;
    ErrorCode one_code = ErrorCode::kInternal, two_code = ErrorCode::kInternal;
    try {
      build_adjacency(c.quads, c.vertices, 1);
    } catch (const Error& e) {
      one = e.what(), one_code = e.code();
    }
    try {
      build_adjacency(c.quads, c.vertices, 2);
    } catch (const Error& e) {
      two = e.what(), two_code = e.code();
    }
    EXPECT_FALSE(one.empty());
    EXPECT_EQ(one, two);
    EXPECT_EQ(one_code, two_code);
  }
}

}  // namespace
}  // namespace qsp
