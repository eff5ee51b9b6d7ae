// permute() (qsp/permute.h): the one renumbering of a mesh, checked against the definition written out
// corner by corner, and its refusals of maps that are no permutation.
#include <gtest/gtest.h>

#include <numeric>
#include <random>

#include "qsp/error.h"
#include "qsp/permute.h"
#include "support/mesh_gen.h"

namespace qsp {
namespace {

// A random permutation of 0..n-1.
std::vector<std::uint32_t> random_permutation(std::size_t n, std::mt19937& rng) {
  std::vector<std::uint32_t> p(n);
  std::iota(p.begin(), p.end(), 0u);
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}

ErrorCode code_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.code();
  }
  ADD_FAILURE() << "no error";
  return ErrorCode::kInternal;
}

// Every corner and position where the definition says, rotated or reversed, on a mesh with several
// components and unreferenced vertices.
TEST(Permute, PutsEveryCornerAndPositionWhereTheDefinitionSays) {
  QuadMesh m = testing::cube(2);
  testing::append(m, testing::grid(3, 2), 5.0f);
  m.positions.insert(m.positions.end(), {7, 8, 9, -1, -2, -3});  // two unreferenced vertices
  std::mt19937 rng(5);
  for (bool reverse : {false, true}) {
    SCOPED_TRACE(reverse);
    const auto vf = random_permutation(m.vertex_count(), rng), ff = random_permutation(m.face_count(), rng);
    std::vector<std::uint8_t> rot(m.face_count());
    for (auto& r : rot) r = static_cast<std::uint8_t>(rng() % 4);
    const QuadMesh out = permute(m, {vf, ff, rot, reverse});
    ASSERT_EQ(out.positions.size(), m.positions.size());
    ASSERT_EQ(out.quads.size(), m.quads.size());
    for (std::size_t i = 0; i < m.vertex_count(); ++i)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(out.positions[3 * i + k], m.positions[3 * vf[i] + k]) << i;
    for (std::size_t f = 0; f < m.face_count(); ++f)
      for (std::uint32_t c = 0; c < 4; ++c) {
        const std::uint32_t from = reverse ? (rot[f] + 4 - c) % 4 : (c + rot[f]) % 4;
        // The result's vertex at that corner is the source's vertex, renumbered.
        EXPECT_EQ(vf[out.quads[4 * f + c]], m.quads[4 * ff[f] + from]) << f << " " << c;
      }
  }
  // No rotation given: corners keep their order; the identity gives the mesh back.
  std::vector<std::uint32_t> iv(m.vertex_count()), ifc(m.face_count());
  std::iota(iv.begin(), iv.end(), 0u);
  std::iota(ifc.begin(), ifc.end(), 0u);
  const QuadMesh same = permute(m, {iv, ifc, {}});
  EXPECT_EQ(same.quads, m.quads);
  EXPECT_EQ(same.positions, m.positions);
}

TEST(Permute, RefusesMapsThatAreNoPermutation) {
  const QuadMesh m = testing::grid(2, 2);  // 9 vertices, 4 faces
  std::vector<std::uint32_t> v(9), f(4);
  std::iota(v.begin(), v.end(), 0u);
  std::iota(f.begin(), f.end(), 0u);
  auto twice = v;
  twice[3] = 4;
  auto beyond = f;
  beyond[0] = 4;
  const std::vector<std::uint8_t> short_rot(3);
  EXPECT_EQ(code_of([&] { permute(m, {twice, f, {}}); }), ErrorCode::kUsage);
  EXPECT_EQ(code_of([&] { permute(m, {v, beyond, {}}); }), ErrorCode::kUsage);
  EXPECT_EQ(code_of([&] { permute(m, {std::span(v).first(8), f, {}}); }), ErrorCode::kUsage);
  EXPECT_EQ(code_of([&] { permute(m, {v, f, short_rot}); }), ErrorCode::kUsage);
  EXPECT_EQ(code_of([&] { inverse_permutation(twice); }), ErrorCode::kUsage);
  // A face of the mesh using a vertex it does not have is the mesh's fault, said as the reader would.
  QuadMesh bad = m;
  bad.quads[5] = 9;
  EXPECT_EQ(code_of([&] { permute(bad, {v, f, {}}); }), ErrorCode::kBadIndex);
  EXPECT_EQ(inverse_permutation(std::vector<std::uint32_t>{2, 0, 1}), (std::vector<std::uint32_t>{1, 2, 0}));
}

}  // namespace
}  // namespace qsp
