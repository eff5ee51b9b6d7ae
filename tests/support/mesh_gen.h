// Test and benchmark meshes made in code: refined cubes, grids, annuli, tori, polyominoes, copies.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "qsp/mesh.h"

namespace qsp::testing {

// Builds a mesh from quads given by integer 3-D corner coordinates, merging equal points.
class MeshBuilder {
 public:
  void quad(const std::array<std::array<int, 3>, 4>& c) {
    for (const auto& p : c) mesh_.quads.push_back(vertex(p));
  }
  std::uint32_t vertex(const std::array<int, 3>& p) {
    const std::uint64_t key = (std::uint64_t(std::uint32_t(p[0] + 4096)) << 42) ^
                              (std::uint64_t(std::uint32_t(p[1] + 4096)) << 21) ^ std::uint32_t(p[2] + 4096);
    auto [it, inserted] = index_.try_emplace(key, static_cast<std::uint32_t>(mesh_.vertex_count()));
    if (inserted)
      for (int k = 0; k < 3; ++k) mesh_.positions.push_back(static_cast<float>(p[k]));
    return it->second;
  }
  QuadMesh take() { return std::move(mesh_); }

 private:
  QuadMesh mesh_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;
};

// Surface of [0,n]^3 as n x n quads per side, outward counter-clockwise. "Refined k times" = n = 2^k.
inline QuadMesh cube(int n) {
  MeshBuilder b;
  // origin, u, v with u x v = outward normal
  const int sides[6][9] = {{0, 0, n, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 0, 1, 0, 1, 0, 0},
                           {n, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0, 0, 0, 1, 0, 1, 0},
                           {0, n, 0, 0, 0, 1, 1, 0, 0}, {0, 0, 0, 1, 0, 0, 0, 0, 1}};
  for (const auto& s : sides)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        auto P = [&](int a, int c) {
          return std::array<int, 3>{s[0] + a * s[3] + c * s[6], s[1] + a * s[4] + c * s[7],
                                    s[2] + a * s[5] + c * s[8]};
        };
        b.quad({P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)});
      }
  return b.take();
}

// Flat polyomino: the unit squares (x, y) listed, counter-clockwise seen from +z.
inline QuadMesh polyomino(const std::vector<std::array<int, 2>>& cells) {
  MeshBuilder b;
  for (auto [x, y] : cells) b.quad({{{x, y, 0}, {x + 1, y, 0}, {x + 1, y + 1, 0}, {x, y + 1, 0}}});
  return b.take();
}

// Rows of '#' cells, top row first (as in shared/known-answers).
inline QuadMesh polyomino(const std::vector<std::string>& rows) {
  std::vector<std::array<int, 2>> cells;
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < rows[r].size(); ++c)
      if (rows[r][c] == '#') cells.push_back({int(c), int(rows.size() - 1 - r)});
  return polyomino(cells);
}

inline QuadMesh grid(int a, int b) {
  std::vector<std::array<int, 2>> cells;
  for (int y = 0; y < b; ++y)
    for (int x = 0; x < a; ++x) cells.push_back({x, y});
  return polyomino(cells);
}

// a quads around, b rows up; positions on a cylinder. twist shifts the top row (torus only).
inline QuadMesh periodic(int a, int b, bool torus, int twist) {
  QuadMesh m;
  const int rows = torus ? b : b + 1;
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < a; ++x) {
      const float t = 6.2831853f * x / a, s = 6.2831853f * y / b;
      const float r = torus ? 3.0f + std::cos(s) : 2.0f;
      m.positions.insert(m.positions.end(),
                         {r * std::cos(t), r * std::sin(t), torus ? std::sin(s) : float(y)});
    }
  auto P = [&](int x, int y) -> std::uint32_t {
    if (torus && y == b) {
      x += twist;
      y = 0;
    }
    return static_cast<std::uint32_t>(y * a + ((x % a) + a) % a);
  };
  for (int y = 0; y < b; ++y)
    for (int x = 0; x < a; ++x)
      m.quads.insert(m.quads.end(), {P(x, y), P(x + 1, y), P(x + 1, y + 1), P(x, y + 1)});
  return m;
}

// n quads around a centre (valence n), each (centre, a_i, b_i, a_i+1): n rotations, n roots tied on
// topology. Positions on two circles, or all at the origin (`flat`), where positions tie them too.
inline QuadMesh fan(int n, bool flat = false) {
  QuadMesh m;
  m.positions = {0, 0, 0};
  for (const float r : {1.0f, 1.25f})
    for (int i = 0; i < n; ++i) {
      const float t = 6.2831853f * (static_cast<float>(i) + (r > 1 ? 0.5f : 0.0f)) / static_cast<float>(n);
      m.positions.insert(m.positions.end(), {flat ? 0 : r * std::cos(t), flat ? 0 : r * std::sin(t), 0});
    }
  const auto a = [n](int i) { return static_cast<std::uint32_t>(1 + (i % n)); };
  for (int i = 0; i < n; ++i)
    m.quads.insert(m.quads.end(), {0, a(i), static_cast<std::uint32_t>(1 + n + i), a(i + 1)});
  return m;
}

// Appends `b` to `a` as another component.
inline void append(QuadMesh& a, const QuadMesh& b, float dx = 0) {
  const auto base = static_cast<std::uint32_t>(a.vertex_count());
  for (std::size_t i = 0; i < b.positions.size(); ++i)
    a.positions.push_back(b.positions[i] + (i % 3 == 0 ? dx : 0));
  for (auto v : b.quads) a.quads.push_back(v + base);
}

// `n` copies of `m` in a row, `dx` apart along x: n interchangeable components (equal canonical codes),
// whose isomorphisms number n! times the product of the copies' symmetries.
inline QuadMesh copies(const QuadMesh& m, int n, float dx) {
  QuadMesh out;
  for (int k = 0; k < n; ++k) append(out, m, dx * float(k));
  return out;
}

// A random renumbering of vertices, reordering of faces and rotation of each face's corners.
// Returns the new-to-old vertex map in `vertex_old` when given.
inline QuadMesh shuffled(const QuadMesh& m, std::uint64_t seed,
                         std::vector<std::uint32_t>* vertex_old = nullptr) {
  std::mt19937_64 rng(seed);
  const auto nv = static_cast<std::uint32_t>(m.vertex_count()),
             nf = static_cast<std::uint32_t>(m.face_count());
  std::vector<std::uint32_t> vperm(nv), fperm(nf), inv(nv);
  std::iota(vperm.begin(), vperm.end(), 0);
  std::iota(fperm.begin(), fperm.end(), 0);
  std::shuffle(vperm.begin(), vperm.end(), rng);
  std::shuffle(fperm.begin(), fperm.end(), rng);
  QuadMesh out;
  out.positions.resize(m.positions.size());
  for (std::uint32_t i = 0; i < nv; ++i) {
    inv[vperm[i]] = i;
    for (int k = 0; k < 3; ++k) out.positions[3 * i + k] = m.positions[3 * vperm[i] + k];
  }
  for (std::uint32_t f : fperm) {
    const auto r = static_cast<std::uint32_t>(rng() % 4);
    for (std::uint32_t k = 0; k < 4; ++k) out.quads.push_back(inv[m.quads[4 * f + (k + r) % 4]]);
  }
  if (vertex_old) *vertex_old = vperm;
  return out;
}

}  // namespace qsp::testing
