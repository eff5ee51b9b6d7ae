// Mesh isomorphism from canonical partitions (§6): compare canonical codes, then pick, among the few
// isomorphisms the codes allow (the symmetries), the one that keeps vertices nearest to where they were.
#include "qsp/match.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <unordered_map>

#include "automorphisms.h"
#include "beside.h"
#include "match_levels.h"
#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/partition.h"
#include "qsp/permute.h"

namespace qsp {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 position(const QuadMesh& m, std::uint32_t v) {
  const float* p = &m.positions[3 * std::size_t(v)];
  return {p[0], p[1], p[2]};
}

double dist2(const Vec3& x, const Vec3& y) {
  const double dx = x[0] - y[0], dy = x[1] - y[1], dz = x[2] - y[2];
  return dx * dx + dy * dy + dz * dz;
}

// The isomorphism count as it is multiplied up: exact while it fits in 64 bits, its base-2 logarithm
// always (a character's hundreds of identical helper parts give k! for k in the hundreds).
struct Count {
  std::uint64_t exact = 1;
  bool fits = true;
  double log2 = 0;

  void times(std::uint64_t x) {
    log2 += x ? std::log2(double(x)) : -HUGE_VAL;
    if (fits && x && exact > std::numeric_limits<std::uint64_t>::max() / x) fits = false;
    if (fits) exact *= x;
  }
  // times k!: the exact product stops at the first overflow (k! passes 2^64 at k = 21), the logarithm
  // comes from lgamma so a million unreferenced vertices cost no million steps.
  void times_factorial(std::uint64_t k) {
    log2 += std::lgamma(double(k) + 1.0) / std::log(2.0);
    for (std::uint64_t i = 2; i <= k && fits; ++i) {
      if (exact > std::numeric_limits<std::uint64_t>::max() / i) fits = false;
      if (fits) exact *= i;
    }
  }
  void store(MatchResult& r) const {
    r.isomorphisms_exact = fits;
    r.isomorphisms = fits ? exact : std::numeric_limits<std::uint64_t>::max();
    r.isomorphisms_log2 = fits ? (exact ? std::log2(double(exact)) : -HUGE_VAL) : log2;
  }
};

// ---- Memory locality ----
// Adjacency, partition and layout walk the mesh face by face; in a file whose vertices and faces were
// renumbered at random (exactly what match is for) every step is a cache miss, and those stages run
// two to three times slower. Such meshes are renumbered first (faces along a Morton curve of their
// first corner, vertices by first use); the result is translated back at the end.

// True when consecutive faces rarely share a vertex, i.e. the face order carries no locality.
bool scrambled(const QuadMesh& m) {
  const std::size_t nf = m.face_count();
  if (nf < 4096) return false;  // fits in cache anyway
  std::size_t near = 0;
  for (std::size_t f = 1; f < nf; ++f) {
    const std::uint32_t* p = &m.quads[4 * (f - 1)];
    const std::uint32_t* q = &m.quads[4 * f];
    bool shared = false;
    for (int i = 0; i < 4 && !shared; ++i)
      for (int j = 0; j < 4 && !shared; ++j) shared = p[i] == q[j];
    near += shared;
  }
  return near < nf / 4;
}

std::uint32_t spread10(std::uint32_t x) {  // 10 bits -> every third bit of 30
  x &= 0x3ff;
  x = (x | x << 16) & 0x30000ff;
  x = (x | x << 8) & 0x300f00f;
  x = (x | x << 4) & 0x30c30c3;
  x = (x | x << 2) & 0x9249249;
  return x;
}

// Renumbers `m` in place; vertex_old / face_old receive new -> old. Corners are not rotated.
void localize(QuadMesh& m, std::vector<std::uint32_t>& vertex_old, std::vector<std::uint32_t>& face_old) {
  const auto nf = static_cast<std::uint32_t>(m.face_count()),
             nv = static_cast<std::uint32_t>(m.vertex_count());
  float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
  for (std::uint32_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], m.positions[3 * std::size_t(v) + k]),
      hi[k] = std::max(hi[k], m.positions[3 * std::size_t(v) + k]);
  float scale[3];
  for (int k = 0; k < 3; ++k) scale[k] = hi[k] > lo[k] ? 1023.0f / (hi[k] - lo[k]) : 0.0f;
  // 30-bit Morton keys, two 15-bit radix passes.
  std::vector<std::uint32_t> key(nf), idx(nf), tmp_key(nf), tmp_idx(nf);
  for (std::uint32_t f = 0; f < nf; ++f) {
    // A bad index or a NaN only costs locality here: build_adjacency reports the index, and the float
    // to integer conversion must stay defined.
    const std::uint32_t v0 = m.quads[4 * std::size_t(f)];
    const float* p = v0 < nv ? &m.positions[3 * std::size_t(v0)] : lo;
    std::uint32_t c = 0;
    for (int k = 0; k < 3; ++k) {
      const float t = (p[k] - lo[k]) * scale[k];
      c |= spread10(t >= 0.0f && t <= 1023.0f ? static_cast<std::uint32_t>(t) : 0u) << k;
    }
    key[f] = c;
    idx[f] = f;
  }
  std::vector<std::uint32_t> count((1u << 15) + 1);
  for (int shift : {0, 15}) {
    std::fill(count.begin(), count.end(), 0);
    for (std::uint32_t f = 0; f < nf; ++f) ++count[((key[f] >> shift) & 0x7fff) + 1];
    for (std::size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
    for (std::uint32_t f = 0; f < nf; ++f) {
      const std::uint32_t slot = count[(key[f] >> shift) & 0x7fff]++;
      tmp_key[slot] = key[f];
      tmp_idx[slot] = idx[f];
    }
    key.swap(tmp_key);
    idx.swap(tmp_idx);
  }
  face_old = std::move(idx);
  std::vector<std::uint8_t> seen(nv, 0);
  vertex_old.clear();
  vertex_old.reserve(nv);
  for (std::uint32_t f : face_old)
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t v = m.quads[4 * std::size_t(f) + c];
      if (v < nv && !seen[v]) {  // an index out of range is build_adjacency's to report
        seen[v] = 1;
        vertex_old.push_back(v);
      }
    }
  for (std::uint32_t v = 0; v < nv; ++v)
    if (!seen[v]) vertex_old.push_back(v);  // unreferenced, in their order
  m = permute(m, {vertex_old, face_old, {}});
}

void finish(MatchInput& in) {
  in.canonical = canonicalize(in.mesh, in.adjacency, partition_motorcycle(in.adjacency));
  const std::size_t n = in.mesh.vertex_count();
  std::array<double, 3> c{0, 0, 0};
  for (std::size_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) c[k] += in.mesh.positions[3 * v + k];
  if (n)
    for (int k = 0; k < 3; ++k) c[k] /= double(n);
  in.centroid = c;
}

using Prepared = MatchInput;

// ---- Levels: per-component keys compared as multisets, coarse to fine ----

// kind, V, F | extraordinary | schematic V, E, patches, torus a, b
using Key = std::array<std::uint64_t, 9>;
constexpr std::size_t kKeyFields[] = {0, 0, 3, 4, 9};  // fields compared at kComponentSizes..kSchematic

Key component_key(const std::vector<ComponentInfo>& info, const CanonicalComponent& c) {
  const ComponentInfo& i = info[c.part.component];
  Key k{static_cast<std::uint64_t>(c.part.kind), i.vertices, i.faces, i.extraordinary, 0, 0, 1, 0, 0};
  if (c.part.kind == ComponentKind::kTorus) {
    k[7] = c.code.a;
    k[8] = c.code.b;
  } else if (c.part.kind != ComponentKind::kAnnulus) {
    k[4] = c.part.schematic.vertex_count;
    k[5] = c.part.schematic.edge_count();
    k[6] = c.part.schematic.patch_count();
  }
  return k;
}

// "disk components with 25 vertices, 16 faces[, ...]" (plural) or "a disk component with ..." (one).
std::string describe(const Key& k, std::size_t fields, bool plural) {
  std::string s = std::string(plural ? "" : "a ") + component_kind_name(static_cast<ComponentKind>(k[0])) +
                  (plural ? " components with " : " component with ") + std::to_string(k[1]) + " vertices, " +
                  std::to_string(k[2]) + " faces";
  if (fields > 3) s += ", " + std::to_string(k[3]) + " extraordinary";
  if (fields > 4) {
    if (k[0] == static_cast<std::uint64_t>(ComponentKind::kTorus))
      s += ", lattice " + std::to_string(k[7]) + "x" + std::to_string(k[8]);
    else if (k[0] != static_cast<std::uint64_t>(ComponentKind::kAnnulus))
      s += ", schematic " + std::to_string(k[4]) + " vertices / " + std::to_string(k[5]) + " edges / " +
           std::to_string(k[6]) + " patches";
  }
  return s;
}

// Empty if the multisets of key prefixes agree, else the first (in key order) that differs.
std::string compare_keys(std::vector<Key> ka, std::vector<Key> kb, std::size_t fields) {
  for (auto* v : {&ka, &kb}) {
    for (Key& k : *v) std::fill(k.begin() + fields, k.end(), 0);
    std::sort(v->begin(), v->end());
  }
  std::size_t i = 0, j = 0;
  while (i < ka.size() || j < kb.size()) {
    const Key& k = (j == kb.size() || (i < ka.size() && ka[i] < kb[j])) ? ka[i] : kb[j];
    std::size_t na = 0, nb = 0;
    while (i < ka.size() && ka[i] == k) ++i, ++na;
    while (j < kb.size() && kb[j] == k) ++j, ++nb;
    if (na != nb)
      return describe(k, fields, true) + ": A has " + std::to_string(na) + ", B has " + std::to_string(nb);
  }
  return {};
}

std::string code_difference(const TopologyCode& x, const TopologyCode& y) {
  if (x.kind == ComponentKind::kTorus && x.twist != y.twist)
    return "torus twist " + std::to_string(x.twist) + " vs " + std::to_string(y.twist);
  if (x.next_ref != y.next_ref) return "schematic connectivity differs";
  if (x.edge_length != y.edge_length) return "schematic edge lengths differ";
  if (x.corner != y.corner) return "patch corners differ";
  return "canonical codes differ";
}

// ---- Assignment (pairing interchangeable components, unreferenced vertices) ----

// Minimum-cost perfect matching of a square cost matrix (Hungarian method with potentials, O(n³)).
// Returns row -> column.
std::vector<std::uint32_t> hungarian(const std::vector<double>& cost, std::size_t n) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0), v(n + 1, 0), minv(n + 1);
  std::vector<std::size_t> p(n + 1, 0), way(n + 1, 0);
  std::vector<char> used(n + 1);
  for (std::size_t i = 1; i <= n; ++i) {
    p[0] = i;
    std::size_t j0 = 0;
    std::fill(minv.begin(), minv.end(), inf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const std::size_t i0 = p[j0];
      double delta = inf;
      std::size_t j1 = 0;
      for (std::size_t j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double cur = cost[(i0 - 1) * n + (j - 1)] - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (std::size_t j = 0; j <= n; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const std::size_t j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  std::vector<std::uint32_t> out(n);
  for (std::size_t j = 1; j <= n; ++j) out[p[j] - 1] = static_cast<std::uint32_t>(j - 1);
  return out;
}

constexpr std::size_t kMaxHungarian = 256;  // exact pairing up to here (O(n³))
constexpr std::size_t kMaxGreedy = 8192;    // greedy nearest pairing up to here (O(n²))

struct Assignment {
  std::vector<std::uint32_t> to;  // index in xs -> index in ys
  bool ambiguous = false;
  bool exhaustive = true;
};

// Pairs points xs[i] with ys[to[i]] minimizing the total squared distance: exactly (Hungarian) up to
// kMaxHungarian points; up to kMaxGreedy, each x in turn takes its nearest free y; beyond, by
// lexicographic order of the points. The last two are exact when both sets are equal and flagged
// non-exhaustive when they are not. Ambiguous when a pairing has an equally good alternative (within
// the tolerance): for Hungarian, swapping two pairs costs nothing; greedily, a tie for the nearest.
Assignment assign(const std::vector<Vec3>& xs, const std::vector<Vec3>& ys, double rel_tol) {
  const std::size_t n = xs.size();
  Assignment out;
  out.to.resize(n);
  if (n == 0) return out;
  if (n == 1) {
    out.to[0] = 0;
    return out;
  }
  if (n > kMaxGreedy) {
    std::vector<std::uint32_t> ix(n), iy(n);
    std::iota(ix.begin(), ix.end(), 0);
    std::iota(iy.begin(), iy.end(), 0);
    std::sort(ix.begin(), ix.end(), [&](auto p, auto q) { return xs[p] < xs[q]; });
    std::sort(iy.begin(), iy.end(), [&](auto p, auto q) { return ys[p] < ys[q]; });
    for (std::size_t k = 0; k < n; ++k) {
      out.to[ix[k]] = iy[k];
      if (xs[ix[k]] != ys[iy[k]]) out.exhaustive = false;
      // Equal points on one side make the pairing arbitrary.
      if (k > 0 && (xs[ix[k]] == xs[ix[k - 1]] || ys[iy[k]] == ys[iy[k - 1]])) out.ambiguous = true;
    }
    return out;
  }
  if (n > kMaxHungarian) {
    std::vector<char> used(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      double best = HUGE_VAL, second = HUGE_VAL;
      std::size_t arg = 0;
      for (std::size_t j = 0; j < n; ++j) {
        if (used[j]) continue;
        const double d = dist2(xs[i], ys[j]);
        if (d < best) {
          second = best;
          best = d;
          arg = j;
        } else if (d < second) {
          second = d;
        }
      }
      used[arg] = 1;
      out.to[i] = static_cast<std::uint32_t>(arg);
      if (best > 0) out.exhaustive = false;
      if (second <= best + rel_tol * best + 1e-12 * dist2(xs[i], Vec3{0, 0, 0})) out.ambiguous = true;
    }
    return out;
  }
  std::vector<double> c(n * n);
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      c[i * n + j] = dist2(xs[i], ys[j]);
      scale = std::max(scale, c[i * n + j]);
    }
  out.to = hungarian(c, n);
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) total += c[i * n + out.to[i]];
  const double tol = rel_tol * total + 1e-12 * scale;
  for (std::size_t i = 0; i < n && !out.ambiguous; ++i)
    for (std::size_t k = i + 1; k < n; ++k) {
      const std::uint32_t j = out.to[i], l = out.to[k];
      if (c[i * n + l] + c[k * n + j] - c[i * n + j] - c[k * n + l] <= tol) {
        out.ambiguous = true;
        break;
      }
    }
  return out;
}

// prefer_order's pairing: xs[i] with the ys[j] whose key (an index in the callers' numbering) is the
// same, when every key of `kx` is one of `ky` (the keys of each side are distinct, and the sides equal
// in size, so that is a bijection). Empty when some key has no partner: pair by positions then.
std::vector<std::uint32_t> pair_by_key(const std::vector<std::uint32_t>& kx,
                                       const std::vector<std::uint32_t>& ky) {
  std::unordered_map<std::uint32_t, std::uint32_t> at;
  at.reserve(ky.size());
  for (std::size_t j = 0; j < ky.size(); ++j) at.emplace(ky[j], static_cast<std::uint32_t>(j));
  std::vector<std::uint32_t> to(kx.size());
  for (std::size_t i = 0; i < kx.size(); ++i) {
    const auto it = at.find(kx[i]);
    if (it == at.end()) return {};
    to[i] = it->second;
  }
  return to;
}

// Pairs points as assign() does, or, with prefer_order, by their keys where pair_by_key can.
Assignment assign_preferring(const std::vector<Vec3>& xs, const std::vector<Vec3>& ys,
                             const std::vector<std::uint32_t>& kx, const std::vector<std::uint32_t>& ky,
                             const MatchOptions& options) {
  if (options.prefer_order) {
    Assignment out;
    out.to = pair_by_key(kx, ky);
    if (!out.to.empty() || xs.empty()) return out;
  }
  return assign(xs, ys, options.tie_tolerance);
}

// ---- Choosing a component's isomorphism ----

struct PairChoice {
  LayoutMap map;  // B's layout map realizing the chosen isomorphism
  ComponentMatch info;
};

// Squared-distance sum between A vertices av[i] and B vertices bv[i], B shifted by t.
double cost_of(const QuadMesh& a, const std::uint32_t* av, const QuadMesh& b, const std::uint32_t* bv,
               std::size_t n, const Vec3& t) {
  double s = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &a.positions[3 * std::size_t(av[i])];
    const float* q = &b.positions[3 * std::size_t(bv[i])];
    const double dx = double(p[0]) - q[0] - t[0], dy = double(p[1]) - q[1] - t[1],
                 dz = double(p[2]) - q[2] - t[2];
    s += dx * dx + dy * dy + dz * dz;
  }
  return s;
}

Vec3 component_centroid(const QuadMesh& m, const CanonicalComponent& c) {
  Vec3 s{0, 0, 0};
  for (std::uint32_t v : c.map.vertex)
    for (int k = 0; k < 3; ++k) s[k] += m.positions[3 * std::size_t(v) + k];
  const double n = double(std::max<std::size_t>(c.map.vertex.size(), 1));
  return {s[0] / n, s[1] / n, s[2] / n};
}

// The smallest index, in the caller's numbering, of a vertex of `c`: equal for two components made of
// the same vertex indices.
std::uint32_t smallest_index(const Prepared& p, const CanonicalComponent& c) {
  std::uint32_t least = kInvalid;
  for (std::uint32_t v : c.map.vertex) least = std::min(least, p.vertex_old.empty() ? v : p.vertex_old[v]);
  return least;
}

// t such that A's positions are compared with B's plus t.
Vec3 shift(const Prepared& pa, const CanonicalComponent& ca, const Prepared& pb, const CanonicalComponent& cb,
           Centering centering) {
  Vec3 x{0, 0, 0}, y{0, 0, 0};
  if (centering == Centering::kComponent) {
    x = component_centroid(pa.mesh, ca);
    y = component_centroid(pb.mesh, cb);
  } else if (centering == Centering::kMesh) {
    x = pa.centroid;
    y = pb.centroid;
  }
  return {x[0] - y[0], x[1] - y[1], x[2] - y[2]};
}

PairChoice choose(const Prepared& pa, const CanonicalComponent& ca, const Prepared& pb,
                  const CanonicalComponent& cb, const MatchOptions& opt) {
  const QuadMesh& a = pa.mesh;
  const QuadMesh& b = pb.mesh;
  const Adjacency& adj = pb.adjacency;
  const Vec3 t = shift(pa, ca, pb, cb, opt.centering);
  const std::size_t n = ca.map.vertex.size();
  PairChoice out;
  out.info.a_faces = static_cast<std::uint32_t>(ca.map.face.size());
  const bool structured = cb.part.kind == ComponentKind::kAnnulus || cb.part.kind == ComponentKind::kTorus;
  // For general components `automorphisms` already is the number of starts.
  const std::vector<std::uint32_t> starts =
      structured || cb.automorphisms > 1 ? canonical_starts(adj, cb) : std::vector<std::uint32_t>{0};
  out.info.isomorphisms = starts.size();
  if (starts.size() <= 1) {
    // No symmetry: the canonical layouts correspond, nothing to choose.
    out.map = cb.map;
    out.info.scored = 1;
    out.info.cost = cost_of(a, ca.map.vertex.data(), b, out.map.vertex.data(), n, t);
    return out;
  }

  // Scale for the absolute tie tolerance: A's bounding-box diagonal.
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (std::uint32_t v : ca.map.vertex) {
    const Vec3 p = position(a, v);
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  const double abs_tol = 1e-12 * double(n) * dist2(lo, hi);
  auto tol = [&](double best) { return opt.tie_tolerance * best + abs_tol; };

  // Lower bounds from probe vertices (a subset of the layout's vertices, same indices on both sides).
  std::vector<std::uint32_t> probe_a, probe_b;
  if (structured) {
    const std::uint32_t w = cb.part.a, rows = cb.part.b;
    for (std::uint32_t x = 0; x < w; ++x) probe_a.push_back(ca.map.vertex[x]);
    for (std::uint32_t y = 1; y < rows; ++y) probe_a.push_back(ca.map.vertex[std::size_t(y) * w]);
  } else {
    probe_a = ca.part.schematic.vertex_mesh;
  }
  // An index in the callers' numbering.
  const auto caller_a = [&](std::uint32_t v) { return pa.vertex_old.empty() ? v : pa.vertex_old[v]; };
  const auto caller_b = [&](std::uint32_t v) { return pb.vertex_old.empty() ? v : pb.vertex_old[v]; };
  // Vertices of `av` an isomorphism taking them to `bv` moves away from their own index.
  const auto moved = [&](const std::uint32_t* av, const std::uint32_t* bv, std::size_t count) {
    std::size_t m = 0;
    for (std::size_t k = 0; k < count; ++k) m += caller_a(av[k]) != caller_b(bv[k]);
    return m;
  };
  // Each candidate's lower bounds, from the probe vertices: of the vertices it moves (prefer_order;
  // else 0) and of its cost. Scored in full in that order. A general component's candidates get bounds
  // from their first kFewProbes probes first and from all only when they come up: those are no larger,
  // so the candidates still come up in the order of their whole bounds, and a fan of n quads (n starts,
  // n probes each) no longer costs n^2.
  struct Candidate {
    std::size_t moved_bound;
    double cost_bound;
    std::uint32_t start;
    bool whole;  // bounds from every probe
    bool operator>(const Candidate& o) const {
      return std::tie(moved_bound, cost_bound, start) > std::tie(o.moved_bound, o.cost_bound, o.start);
    }
  };
  constexpr std::size_t kFewProbes = 32;
  detail::Walk walk;
  // General components: the darts where the canonical traversal first reaches each vertex.
  std::vector<std::uint32_t> first;
  if (!structured) {
    const Schematic& sb = cb.part.schematic;  // labelled by that traversal: dart i is its i-th
    std::vector<std::uint8_t> seen;
    detail::first_reached(
        sb, sb.dart_count(), [](std::uint32_t i) { return i; }, seen, first);
  }
  const auto bounds = [&](std::uint32_t s, bool whole) {
    const std::size_t count = whole || structured ? probe_a.size() : std::min(kFewProbes, probe_a.size());
    probe_b.clear();
    if (structured) {
      std::uint32_t h = s;
      for (std::uint32_t x = 0; x < cb.part.a; ++x, h = adj.next(adj.twin[adj.next(h)]))
        probe_b.push_back(adj.origin[h]);
      h = s;
      for (std::uint32_t y = 1; y < cb.part.b; ++y) {
        h = adj.twin[adj.next(adj.next(h))];
        probe_b.push_back(adj.origin[h]);
      }
    } else {
      // What canonical_from_start(adj, cb, s).schematic.vertex_mesh begins with, walked only so far.
      const Schematic& sb = cb.part.schematic;
      walk.start(sb, s);
      for (std::size_t j = 0; j < count; ++j)
        probe_b.push_back(sb.vertex_mesh[sb.dart_vertex[walk.at(first[j])]]);
    }
    return Candidate{opt.prefer_order ? moved(probe_a.data(), probe_b.data(), count) : 0,
                     cost_of(a, probe_a.data(), b, probe_b.data(), count, t), s, count == probe_a.size()};
  };
  std::vector<Candidate> heap;
  heap.reserve(starts.size());
  for (std::uint32_t s : starts) heap.push_back(bounds(s, false));
  std::make_heap(heap.begin(), heap.end(), std::greater<>());
  // The candidate with the next smallest whole bounds, or none.
  const auto next = [&]() -> std::optional<Candidate> {
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end(), std::greater<>());
      const Candidate c = heap.back();
      heap.pop_back();
      if (c.whole) return c;
      heap.push_back(bounds(c.start, true));
      std::push_heap(heap.begin(), heap.end(), std::greater<>());
    }
    return std::nullopt;
  };

  // Full scores (vertices moved, cost) in order of lower bounds, until no remaining candidate can tie
  // or beat the best. `rival`: the nearest other candidate moving as few vertices.
  std::size_t best_moved = SIZE_MAX;
  double best = HUGE_VAL, rival = HUGE_VAL;
  while (const std::optional<Candidate> next_candidate = next()) {
    const Candidate& c = *next_candidate;
    if (c.moved_bound > best_moved || (c.moved_bound == best_moved && c.cost_bound > best + tol(best))) break;
    if (out.info.scored == opt.max_full_evaluations) {
      out.info.exhaustive = false;
      break;
    }
    LayoutMap m = layout_to_mesh(canonical_from_start(adj, cb, c.start), adj);
    const double cost = cost_of(a, ca.map.vertex.data(), b, m.vertex.data(), n, t);
    const std::size_t mv = opt.prefer_order ? moved(ca.map.vertex.data(), m.vertex.data(), n) : 0;
    ++out.info.scored;
    if (mv < best_moved) {
      rival = HUGE_VAL;  // the previous best moves more: no rival
    } else if (mv > best_moved) {
      continue;
    } else if (cost >= best) {
      rival = std::min(rival, cost);
      continue;
    } else {
      rival = best;
    }
    best_moved = mv;
    best = cost;
    out.map = std::move(m);
  }
  out.info.cost = best;
  out.info.ambiguous = !out.info.exhaustive || rival <= best + tol(best);
  return out;
}

}  // namespace

namespace detail {

MatchLevel quad_difference(const MatchInput& pa, const MatchInput& pb, std::string& why_out) {
  auto say = [&](MatchLevel level, std::string why) {
    why_out = std::move(why);
    return level;
  };
  if (pa.adjacency.component_count != pb.adjacency.component_count)
    return say(MatchLevel::kComponentCount, "A has " + std::to_string(pa.adjacency.component_count) +
                                                ", B has " + std::to_string(pb.adjacency.component_count));
  const auto& ca = pa.canonical.components;
  const auto& cb = pb.canonical.components;

  // Codes: both lists are in canonical order, so isomorphic ⇔ equal element by element. Equal codes
  // imply equal keys, so the per-component counts are only needed to say why codes differ.
  bool same = true;
  for (std::size_t i = 0; i < ca.size() && same; ++i) same = ca[i].code == cb[i].code;
  if (!same) {
    const auto info_a = component_info(pa.adjacency), info_b = component_info(pb.adjacency);
    std::vector<Key> ka, kb;
    for (const auto& c : ca) ka.push_back(component_key(info_a, c));
    for (const auto& c : cb) kb.push_back(component_key(info_b, c));
    for (MatchLevel level :
         {MatchLevel::kComponentSizes, MatchLevel::kExtraordinary, MatchLevel::kSchematic}) {
      std::string why = compare_keys(ka, kb, kKeyFields[static_cast<int>(level)]);
      if (!why.empty()) return say(level, why);
    }
    // Name the first A component (in code order) with no equal code in B, and how it differs from a B
    // component of the same sizes.
    std::size_t i = 0, j = 0;
    while (i < ca.size() && j < cb.size() && !(ca[i].code < cb[j].code)) {
      if (ca[i].code == cb[j].code) ++i;
      ++j;
    }
    if (i < ca.size())
      for (std::size_t y = 0; y < cb.size(); ++y)
        if (kb[y] == ka[i])
          return say(MatchLevel::kCode,
                     describe(ka[i], 9, false) + " of A: " + code_difference(ca[i].code, cb[y].code));
    return say(MatchLevel::kCode, "canonical codes differ");
  }
  const auto& ua = pa.canonical.unreferenced;
  const auto& ub = pb.canonical.unreferenced;
  if (ua.size() != ub.size())
    return say(MatchLevel::kUnreferenced,
               "A has " + std::to_string(ua.size()) + ", B has " + std::to_string(ub.size()));

  return MatchLevel::kNone;
}

std::vector<std::uint32_t> pair_nearest(const std::vector<std::array<double, 3>>& xs,
                                        const std::vector<std::array<double, 3>>& ys, double tie_tolerance,
                                        bool& ambiguous, bool& exhaustive) {
  Assignment a = assign(xs, ys, tie_tolerance);
  ambiguous |= a.ambiguous;
  exhaustive &= a.exhaustive;
  return std::move(a.to);
}

}  // namespace detail

const char* match_level_name(MatchLevel level) noexcept {
  switch (level) {
    case MatchLevel::kNone:
      return "none";
    case MatchLevel::kComponentCount:
      return "component count";
    case MatchLevel::kComponentSizes:
      return "component sizes";
    case MatchLevel::kExtraordinary:
      return "extraordinary vertices";
    case MatchLevel::kSchematic:
      return "schematic";
    case MatchLevel::kCode:
      return "canonical code";
    case MatchLevel::kUnreferenced:
      return "unreferenced vertices";
    case MatchLevel::kFaceDegrees:
      return "face degrees";
    case MatchLevel::kRegions:
      return "non-quad regions";
    case MatchLevel::kGlue:
      return "cut vertices";
  }
  return "?";
}

MatchInput prepare_match(QuadMesh mesh) {
  MatchInput in;
  if (!scrambled(mesh)) {
    in.mesh = std::move(mesh);
    in.adjacency = build_adjacency(in.mesh);
  } else {
    in.mesh = mesh;
    try {
      localize(in.mesh, in.vertex_old, in.face_old);
      in.adjacency = build_adjacency(in.mesh);
    } catch (const Error&) {
      // Say what is wrong in the caller's numbering: the same check on the original mesh.
      build_adjacency(mesh);
      throw;
    }
  }
  finish(in);
  return in;
}

MatchInput prepare_match(const QuadMesh& mesh, const Adjacency& adjacency) {
  MatchInput in;
  in.mesh = mesh;
  in.adjacency = adjacency;
  finish(in);
  return in;
}

MatchResult match(const QuadMesh& a, const QuadMesh& b, const MatchOptions& options) {
  // The two meshes are independent: prepare them side by side. A's error wins if both fail.
  auto second = beside(true, [&b] { return prepare_match(b); });
  const MatchInput pa = prepare_match(a);  // if it throws, second's destructor waits for it
  const MatchInput pb = second.get();
  return match(pa, pb, options);
}

namespace {

MatchResult match_oriented(const MatchInput& pa, const MatchInput& pb, const MatchOptions& options);

// The mesh with every face's corners reversed (v0 v3 v2 v1): orientation-reversing isomorphisms of the
// original are the orientation-preserving ones of this, with the same vertex and face numbers.
QuadMesh reversed(const QuadMesh& m) {
  QuadMesh out = m;
  for (std::size_t f = 0; f < out.face_count(); ++f) std::swap(out.quads[4 * f + 1], out.quads[4 * f + 3]);
  return out;
}

// A match of A against B with every face reversed, in B's numbering as its caller gave it, with
// rotations for B's own corners: A's corner c is B's corner (rotation - c) % 4.
MatchResult mirrored_match(const MatchInput& a, const MatchInput& b, const MatchOptions& options) {
  MatchResult r = match_oriented(a, prepare_match(reversed(b.mesh)), options);
  if (!r.isomorphic) return r;
  r.mirrored = true;
  // reversed(b.mesh) keeps b.mesh's (possibly renumbered) order: map back as match() does.
  for (std::uint32_t& v : r.vertex)
    if (!b.vertex_old.empty()) v = b.vertex_old[v];
  for (std::size_t f = 0; f < r.face.size(); ++f) {
    if (!b.face_old.empty()) r.face[f] = b.face_old[r.face[f]];
    // Reversed corner k is B's corner (4 - k) % 4, k = (c + r) % 4.
    r.rotation[f] = static_cast<std::uint8_t>((4 - r.rotation[f]) & 3u);
  }
  return r;
}

}  // namespace

MatchResult match(const MatchInput& pa, const MatchInput& pb, const MatchOptions& options) {
  MatchResult r = match_oriented(pa, pb, options);
  // Reversing every face keeps the component sizes and extraordinary vertices: only a difference in the
  // schematic (the right-hand rule depends on orientation) or the code can be a mirror.
  if (r.isomorphic || options.mirror == Mirror::kNo ||
      (r.level != MatchLevel::kSchematic && r.level != MatchLevel::kCode))
    return r;
  MatchResult m = mirrored_match(pa, pb, options);
  if (m.isomorphic && options.mirror == Mirror::kAccept) return m;
  r.mirror_would_match = m.isomorphic;
  return r;
}

namespace {

MatchResult match_oriented(const MatchInput& pa, const MatchInput& pb, const MatchOptions& options) {
  MatchResult r;
  auto differ = [&](MatchLevel level, std::string why) {
    r.level = level;
    r.reason = std::string(match_level_name(level)) + ": " + why;
    return r;
  };
  const QuadMesh& a = pa.mesh;
  const QuadMesh& b = pb.mesh;
  {
    std::string why;
    const MatchLevel level = detail::quad_difference(pa, pb, why);
    if (level != MatchLevel::kNone) return differ(level, why);
  }
  const auto& ca = pa.canonical.components;
  const auto& cb = pb.canonical.components;
  const auto& ua = pa.canonical.unreferenced;
  const auto& ub = pb.canonical.unreferenced;

  r.isomorphic = true;
  r.vertex.assign(a.vertex_count(), kInvalid);
  r.face.assign(a.face_count(), kInvalid);
  r.rotation.assign(a.face_count(), 0);
  Count count;
  r.components.resize(ca.size());
  const bool centered = options.centering != Centering::kNone;
  auto rel = [&](const Prepared& p, Vec3 x) {
    if (centered)
      for (int k = 0; k < 3; ++k) x[k] -= p.centroid[k];
    return x;
  };

  // Runs of equal codes are interchangeable components: pair them by centroid.
  for (std::size_t i = 0; i < ca.size();) {
    std::size_t j = i + 1;
    while (j < ca.size() && ca[j].code == ca[i].code) ++j;
    std::vector<Vec3> xs, ys;
    std::vector<std::uint32_t> kx, ky;  // prefer_order: each component's smallest vertex index
    for (std::size_t k = i; k < j; ++k) {
      xs.push_back(rel(pa, component_centroid(a, ca[k])));
      ys.push_back(rel(pb, component_centroid(b, cb[k])));
      if (options.prefer_order) {
        kx.push_back(smallest_index(pa, ca[k]));
        ky.push_back(smallest_index(pb, cb[k]));
      }
    }
    const Assignment pairing = assign_preferring(xs, ys, kx, ky, options);
    r.ambiguous |= pairing.ambiguous;
    r.exhaustive &= pairing.exhaustive;
    count.times_factorial(j - i);
    for (std::size_t k = i; k < j; ++k) {
      const CanonicalComponent& x = ca[k];
      const CanonicalComponent& y = cb[i + pairing.to[k - i]];
      PairChoice choice = choose(pa, x, pb, y, options);
      r.components[k] = choice.info;
      count.times(choice.info.isomorphisms);
      r.ambiguous |= choice.info.ambiguous;
      r.exhaustive &= choice.info.exhaustive;
      r.cost += choice.info.cost;
      const LayoutMap& m = choice.map;
      if (m.vertex.size() != x.map.vertex.size() || m.face.size() != x.map.face.size())
        throw Error(ErrorCode::kInternal, "match: equal codes gave layouts of different sizes");
      for (std::size_t v = 0; v < m.vertex.size(); ++v) r.vertex[x.map.vertex[v]] = m.vertex[v];
      for (std::size_t f = 0; f < m.face.size(); ++f) {
        r.face[x.map.face[f]] = m.face[f];
        r.rotation[x.map.face[f]] = static_cast<std::uint8_t>((m.rotation[f] - x.map.rotation[f]) & 3u);
      }
    }
    i = j;
  }

  // Unreferenced vertices: any pairing is an isomorphism; take the nearest.
  {
    std::vector<Vec3> xs, ys;
    std::vector<std::uint32_t> kx, ky;
    for (std::uint32_t v : ua) xs.push_back(rel(pa, position(a, v)));
    for (std::uint32_t v : ub) ys.push_back(rel(pb, position(b, v)));
    if (options.prefer_order) {
      for (std::uint32_t v : ua) kx.push_back(pa.vertex_old.empty() ? v : pa.vertex_old[v]);
      for (std::uint32_t v : ub) ky.push_back(pb.vertex_old.empty() ? v : pb.vertex_old[v]);
    }
    const Assignment pairing = assign_preferring(xs, ys, kx, ky, options);
    r.ambiguous |= pairing.ambiguous;
    r.exhaustive &= pairing.exhaustive;
    count.times_factorial(ua.size());
    for (std::size_t k = 0; k < ua.size(); ++k) {
      r.vertex[ua[k]] = ub[pairing.to[k]];
      r.cost += dist2(xs[k], ys[pairing.to[k]]);
    }
  }
  count.store(r);
  for (std::uint32_t v : r.vertex)
    if (v == kInvalid) throw Error(ErrorCode::kInternal, "match: a vertex of A was left unmapped");
  for (std::uint32_t f : r.face)
    if (f == kInvalid) throw Error(ErrorCode::kInternal, "match: a face of A was left unmapped");
  // Back to the callers' numbering (prepare_match may have renumbered either mesh; corners kept).
  if (!pa.vertex_old.empty() || !pb.vertex_old.empty()) {
    auto va = [&](std::uint32_t v) { return pa.vertex_old.empty() ? v : pa.vertex_old[v]; };
    auto vb = [&](std::uint32_t v) { return pb.vertex_old.empty() ? v : pb.vertex_old[v]; };
    auto fa = [&](std::uint32_t f) { return pa.face_old.empty() ? f : pa.face_old[f]; };
    auto fb = [&](std::uint32_t f) { return pb.face_old.empty() ? f : pb.face_old[f]; };
    std::vector<std::uint32_t> vertex(r.vertex.size()), face(r.face.size());
    std::vector<std::uint8_t> rotation(r.face.size());
    for (std::uint32_t v = 0; v < vertex.size(); ++v) vertex[va(v)] = vb(r.vertex[v]);
    for (std::uint32_t f = 0; f < face.size(); ++f) {
      face[fa(f)] = fb(r.face[f]);
      rotation[fa(f)] = r.rotation[f];
    }
    r.vertex = std::move(vertex);
    r.face = std::move(face);
    r.rotation = std::move(rotation);
  }
  return r;
}

}  // namespace

std::string isomorphism_count_text(const MatchResult& r) {
  if (!r.isomorphic) return "0";
  if (r.isomorphisms_exact) return std::to_string(r.isomorphisms);
  const double decimal = r.isomorphisms_log2 * std::log10(2.0);
  const double exponent = std::floor(decimal);
  char buf[64];
  std::snprintf(buf, sizeof buf, "about 2^%.1f (%.1fe%.0f)", r.isomorphisms_log2,
                std::pow(10.0, decimal - exponent), exponent);
  return buf;
}

QuadMesh reorder_like(const QuadMesh& in, const MatchResult& m) {
  if (!m.isomorphic)
    throw Error(ErrorCode::kUsage, "reorder_like: the meshes are not isomorphic: " + m.reason);
  return permute(in, {m.vertex, m.face, m.rotation, m.mirrored});
}

bool verify_match(const QuadMesh& a, const QuadMesh& b, const MatchResult& m, std::string* why) {
  // The polygon meshes' check, every face a quad: one definition of a verified map.
  PolygonMatchResult p;
  p.isomorphic = m.isomorphic;
  p.mirrored = m.mirrored;
  p.vertex = m.vertex;
  p.face = m.face;
  p.rotation.assign(m.rotation.begin(), m.rotation.end());
  return verify_polygon_match(polygon_mesh(a), polygon_mesh(b), p, why);
}

}  // namespace qsp
