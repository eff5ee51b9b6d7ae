// Highway meshes (paper §8, Figures 10-11): quad meshes built from a line-segment arrangement whose
// optimal structured partition is known, 4j+10n-2k schematic vertices, 6j+12n-3k edges and j+3n-k
// patches for n segments, j crossings ("junctions") and k the largest non-crossing subset.
//
// The mesh is built combinatorially (Figure 11's view): segment s with x crossings becomes a highway
// of two lanes, v = 0..2 across (lines L1, L2, L3) and u = 0..3x+3 along. Lane L2-L3 runs the whole
// length; lane L1-L2 stops one quad short at each end (the perpendicular P_in at u = 1 and u = 3x+2
// crosses all three lines, P_out at u = 0 and 3x+3 only two), which makes L2 x P_in a boundary vertex
// with four edges: the extraordinary vertex near each end. Crossing i (1-based, in order along s)
// occupies u = 3i-1..3i+1, a 2x2 block shared with the crossing highway (the junction); between
// junctions and the ends there is one quad. Header-only; used by tests/test_smaller.cpp and
// tools/highway/highway.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "qsp/mesh.h"

namespace qsp::highway {

struct Point {
  std::int64_t x = 0, y = 0;
};
struct Segment {
  Point a, b;
};

// A set of segments that meet only in proper crossings (no shared or touching endpoints, no overlaps,
// no three through one point), with the crossing pairs.
struct Arrangement {
  std::vector<Segment> segments;
  std::vector<std::pair<int, int>> crossings;  // (s, t) with s < t
};

inline std::int64_t cross(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by) {
  return ax * by - ay * bx;
}
inline int sign(std::int64_t v) { return (v > 0) - (v < 0); }
inline int orient(const Point& p, const Point& q, const Point& r) {
  return sign(cross(q.x - p.x, q.y - p.y, r.x - p.x, r.y - p.y));
}

// 0: disjoint, 1: proper crossing, -1: touching, overlapping or collinear contact (not allowed).
inline int classify(const Segment& s, const Segment& t) {
  const int o1 = orient(s.a, s.b, t.a), o2 = orient(s.a, s.b, t.b);
  const int o3 = orient(t.a, t.b, s.a), o4 = orient(t.a, t.b, s.b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return 1;
  auto on = [](const Point& p, const Point& q, const Point& r) {  // r on segment pq, given collinear
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
  };
  if ((o1 == 0 && on(s.a, s.b, t.a)) || (o2 == 0 && on(s.a, s.b, t.b)) || (o3 == 0 && on(t.a, t.b, s.a)) ||
      (o4 == 0 && on(t.a, t.b, s.b)))
    return -1;
  return 0;
}

// Parameter of t's crossing along s as a fraction num/den with den > 0.
inline std::pair<std::int64_t, std::int64_t> crossing_param(const Segment& s, const Segment& t) {
  const std::int64_t dx = s.b.x - s.a.x, dy = s.b.y - s.a.y, ex = t.b.x - t.a.x, ey = t.b.y - t.a.y;
  std::int64_t num = cross(t.a.x - s.a.x, t.a.y - s.a.y, ex, ey), den = cross(dx, dy, ex, ey);
  if (den < 0) num = -num, den = -den;
  return {num, den};
}

// n random segments with endpoints in [0, size]^2, redrawn until they meet only in proper crossings
// and no point lies on three of them. Deterministic in `seed`.
inline Arrangement random_arrangement(std::uint64_t seed, int n, int size = 24) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> coord(0, size);
  Arrangement arr;
  int attempts = 0;
  while (static_cast<int>(arr.segments.size()) < n) {
    if (++attempts > 100000) throw std::runtime_error("highway: cannot place segments");
    Segment s{{coord(rng), coord(rng)}, {coord(rng), coord(rng)}};
    if (s.a.x == s.b.x && s.a.y == s.b.y) continue;
    bool ok = true;
    std::vector<int> crossed;
    for (int t = 0; t < static_cast<int>(arr.segments.size()) && ok; ++t) {
      const int c = classify(arr.segments[t], s);
      if (c < 0) ok = false;
      if (c == 1) crossed.push_back(t);
    }
    // No crossing point shared with another crossing: compare parameters along each old segment.
    for (std::size_t i = 0; i < crossed.size() && ok; ++i) {
      const Segment& t = arr.segments[crossed[i]];
      const auto p = crossing_param(t, s);
      for (const auto& [a, b] : arr.crossings) {
        if (a != crossed[i] && b != crossed[i]) continue;
        const auto q = crossing_param(t, arr.segments[a == crossed[i] ? b : a]);
        if (p.first * q.second == q.first * p.second) ok = false;
      }
    }
    if (!ok) continue;
    const int id = static_cast<int>(arr.segments.size());
    arr.segments.push_back(s);
    for (int t : crossed) arr.crossings.emplace_back(t, id);
  }
  std::sort(arr.crossings.begin(), arr.crossings.end());
  return arr;
}

// Largest set of pairwise non-crossing segments, by brute force over subsets (n <= 24).
inline std::vector<int> max_noncrossing(const Arrangement& arr) {
  const int n = static_cast<int>(arr.segments.size());
  if (n > 24) throw std::runtime_error("highway: brute force limited to 24 segments");
  std::vector<std::uint32_t> conflict(n, 0);
  for (const auto& [s, t] : arr.crossings) {
    conflict[s] |= 1u << t;
    conflict[t] |= 1u << s;
  }
  std::uint32_t best = 0;
  int best_size = -1;
  for (std::uint32_t mask = 0; mask < (1u << n); ++mask) {
    const int size = __builtin_popcount(mask);
    if (size <= best_size) continue;
    bool ok = true;
    for (int s = 0; s < n && ok; ++s)
      if ((mask >> s & 1) && (conflict[s] & mask)) ok = false;
    if (ok) {
      best = mask;
      best_size = size;
    }
  }
  std::vector<int> out;
  for (int s = 0; s < n; ++s)
    if (best >> s & 1) out.push_back(s);
  return out;
}

struct Counts {
  std::int64_t vertices = 0, edges = 0, patches = 0;
};
// The optimum of §8 for a casing with k visible segments.
inline Counts optimal_counts(std::int64_t n, std::int64_t j, std::int64_t k) {
  return {4 * j + 10 * n - 2 * k, 6 * j + 12 * n - 3 * k, j + 3 * n - k};
}

struct HighwayMesh {
  QuadMesh mesh;
  int n = 0, j = 0;
  std::vector<int> length;                     // per segment: U = 3x+3 (quads along lane L2-L3)
  std::vector<std::vector<int>> junctions;     // per segment: crossing ids in order along it
  std::vector<std::pair<int, int>> crossings;  // per crossing id: (s, t)
  std::map<std::tuple<int, int, int>, std::uint32_t> vertex;  // (segment, u, v) -> mesh vertex
};

// Builds the highway mesh of `arr` (see the header comment).
inline HighwayMesh build(const Arrangement& arr) {
  HighwayMesh h;
  h.n = static_cast<int>(arr.segments.size());
  h.j = static_cast<int>(arr.crossings.size());
  h.crossings = arr.crossings;
  h.junctions.assign(h.n, {});
  for (int c = 0; c < h.j; ++c) {
    h.junctions[arr.crossings[c].first].push_back(c);
    h.junctions[arr.crossings[c].second].push_back(c);
  }
  // Order each segment's crossings along it.
  for (int s = 0; s < h.n; ++s) {
    auto& js = h.junctions[s];
    auto param = [&](int c) {
      const int t = arr.crossings[c].first == s ? arr.crossings[c].second : arr.crossings[c].first;
      return crossing_param(arr.segments[s], arr.segments[t]);
    };
    std::sort(js.begin(), js.end(), [&](int c1, int c2) {
      const auto p = param(c1), q = param(c2);
      return p.first * q.second < q.first * p.second;
    });
    h.length.push_back(3 * static_cast<int>(js.size()) + 3);
  }
  // Points of every segment's own grid, then junction points glued (union-find).
  std::vector<std::array<int, 3>> key;  // id -> (s, u, v)
  std::map<std::tuple<int, int, int>, int> id;
  for (int s = 0; s < h.n; ++s) {
    const int U = h.length[s];
    for (int u = 0; u <= U; ++u)
      for (int v = 0; v <= 2; ++v) {
        if (v == 0 && (u == 0 || u == U)) continue;
        id[{s, u, v}] = static_cast<int>(key.size());
        key.push_back({s, u, v});
      }
  }
  std::vector<int> parent(key.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto index_on = [&](int s, int c) {
    const auto& js = h.junctions[s];
    return static_cast<int>(std::find(js.begin(), js.end(), c) - js.begin()) + 1;
  };
  for (int c = 0; c < h.j; ++c) {
    const auto [s, t] = arr.crossings[c];
    const Segment &S = arr.segments[s], &T = arr.segments[t];
    const bool left = cross(S.b.x - S.a.x, S.b.y - S.a.y, T.b.x - T.a.x, T.b.y - T.a.y) > 0;
    const int bs = 3 * index_on(s, c) - 1, bt = 3 * index_on(t, c) - 1;
    for (int a = 0; a <= 2; ++a)
      for (int b = 0; b <= 2; ++b) {
        // t crossing s from right to left: t's u runs along s's v, t's v against s's u.
        const int ta = left ? b : 2 - b, tb = left ? 2 - a : a;
        const int x = find(id.at({s, bs + a, b})), y = find(id.at({t, bt + ta, tb}));
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
  }
  std::vector<std::uint32_t> mesh_id(key.size(), kInvalid);
  for (std::size_t i = 0; i < key.size(); ++i) {
    const int r = find(static_cast<int>(i));
    if (mesh_id[r] == kInvalid) {
      mesh_id[r] = static_cast<std::uint32_t>(h.mesh.vertex_count());
      // Position: along the segment, lanes offset sideways (only for looking at the mesh).
      const auto [s, u, v] = key[r];
      const Segment& S = arr.segments[s];
      const double len = std::hypot(double(S.b.x - S.a.x), double(S.b.y - S.a.y));
      const double t = (u + 0.5) / (h.length[s] + 1.0), off = 0.15 * (v - 1);
      const double nx = -(S.b.y - S.a.y) / len, ny = (S.b.x - S.a.x) / len;
      h.mesh.positions.push_back(static_cast<float>(S.a.x + t * (S.b.x - S.a.x) + off * nx));
      h.mesh.positions.push_back(static_cast<float>(S.a.y + t * (S.b.y - S.a.y) + off * ny));
      h.mesh.positions.push_back(0.0f);
    }
    mesh_id[i] = mesh_id[r];
    h.vertex[{key[i][0], key[i][1], key[i][2]}] = mesh_id[r];
  }
  // Quads, counter-clockwise in each segment's (u, v) frame; a junction's four quads once, from the
  // crossing's first segment.
  for (int s = 0; s < h.n; ++s) {
    const int U = h.length[s];
    std::vector<std::uint8_t> skip(U, 0);
    for (int c : h.junctions[s])
      if (arr.crossings[c].second == s) {
        const int b = 3 * index_on(s, c) - 1;
        skip[b] = skip[b + 1] = 1;
      }
    for (int u = 0; u < U; ++u) {
      if (skip[u]) continue;
      for (int v = 0; v < 2; ++v) {
        if (v == 0 && (u == 0 || u == U - 1)) continue;
        for (auto [du, dv] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}})
          h.mesh.quads.push_back(h.vertex.at({s, u + du, v + dv}));
      }
    }
  }
  return h;
}

// Half-edge from mesh vertex a to mesh vertex b (kInvalid if they are not adjacent).
inline std::uint32_t halfedge(const Adjacency& adj, std::uint32_t a, std::uint32_t b) {
  const std::uint32_t h0 = adj.vertex_halfedge[a];
  std::uint32_t h = h0;
  do {
    if (adj.dest(h) == b) return h;
    h = adj.rotate(h);
  } while (h != h0);
  return kInvalid;
}

// The optimal cut set of §8 for the casing where the `visible` segments pass over every crossing
// (other crossings: the first segment passes over): at each junction the two outer lines of the
// upper highway; along each visible segment its middle line L2 from one extraordinary vertex to the
// other; at each end of an invisible segment the edge P_in from its extraordinary vertex to the
// boundary. Boundary edges are not listed (partition_from_cuts always cuts them).
inline std::vector<std::uint32_t> optimal_cuts(const HighwayMesh& h, const Adjacency& adj,
                                               const std::vector<int>& visible) {
  std::vector<std::uint8_t> vis(h.n, 0);
  for (int s : visible) vis[s] = 1;
  std::vector<std::uint32_t> cuts;
  auto cut = [&](int s, int u0, int v0, int u1, int v1) {
    const std::uint32_t e = halfedge(adj, h.vertex.at({s, u0, v0}), h.vertex.at({s, u1, v1}));
    if (e == kInvalid) throw std::runtime_error("highway: cut between non-adjacent vertices");
    cuts.push_back(e);
  };
  for (int c = 0; c < h.j; ++c) {
    const auto [s, t] = h.crossings[c];
    if (vis[s] && vis[t]) throw std::runtime_error("highway: visible segments cross");
    const int over = vis[t] ? t : s;
    const auto& js = h.junctions[over];
    const int b = 3 * static_cast<int>(std::find(js.begin(), js.end(), c) - js.begin() + 1) - 1;
    for (int v : {0, 2})
      for (int u = b; u < b + 2; ++u) cut(over, u, v, u + 1, v);
  }
  for (int s = 0; s < h.n; ++s) {
    const int U = h.length[s];
    if (vis[s]) {
      for (int u = 1; u < U - 1; ++u) cut(s, u, 1, u + 1, 1);
    } else {
      cut(s, 1, 1, 1, 2);
      cut(s, U - 1, 1, U - 1, 2);
    }
  }
  return cuts;
}

}  // namespace qsp::highway
