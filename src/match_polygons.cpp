// Isomorphism of polygon meshes (qsp/match.h): the quad submesh's canonical form, then the canonical
// region codes and glue (qsp/regions.h), all made on the topology alone: the positions those stages
// break ties by are replaced by vertex colours that no renumbering changes.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "match_levels.h"
#include "qsp/error.h"
#include "qsp/match.h"
#include "qsp/partition.h"
#include "qsp/permute.h"
#include "qsp/polymesh.h"

namespace qsp {
namespace {

using Vec3 = std::array<double, 3>;

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finalizer
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

std::size_t distinct(std::vector<std::uint64_t> xs) {
  std::sort(xs.begin(), xs.end());
  return static_cast<std::size_t>(std::unique(xs.begin(), xs.end()) - xs.begin());
}

// Colour refinement: a vertex starts with its number of corners; each round it takes, with its own
// colour, the multiset (a commutative sum of hashes) of its corners' (face degree, colour of the next
// corner's vertex, colour of the previous corner's vertex), until the number of classes stops growing
// (64 rounds at most). Every step is invariant under renumbering vertices and faces and rotating corner
// lists, and orientation-sensitive; a hash collision only merges classes.
std::vector<std::uint64_t> vertex_colours(const PolygonMesh& m) {
  const std::size_t nv = m.vertex_count(), nf = m.face_count();
  std::vector<std::uint64_t> colour(nv, 0), next(nv);
  for (std::uint32_t v : m.corners) ++colour[v];
  for (auto& c : colour) c = mix(c);
  std::size_t classes = distinct(colour);
  for (int round = 0; round < 64; ++round) {
    for (std::size_t v = 0; v < nv; ++v) next[v] = mix(colour[v] ^ 0x5bd1e995u);
    for (std::size_t f = 0; f < nf; ++f) {
      const std::uint32_t b = m.face_offsets[f], d = m.degree(f);
      for (std::uint32_t i = 0; i < d; ++i) {
        const std::uint32_t v = m.corners[b + i], after = m.corners[b + (i + 1) % d],
                            before = m.corners[b + (i + d - 1) % d];
        next[v] += mix(mix(mix(d) ^ colour[after]) + colour[before]);
      }
    }
    for (std::size_t v = 0; v < nv; ++v) next[v] = mix(next[v]);
    colour.swap(next);
    const std::size_t now = distinct(colour);
    if (now <= classes || now == nv) break;  // stable, or every vertex told apart
    classes = now;
  }
  return colour;
}

// The colours as positions canonicalize and canonical_regions compare: 21 bits per coordinate, integers a
// float holds exactly.
std::vector<float> colour_positions(const std::vector<std::uint64_t>& colour) {
  std::vector<float> out(3 * colour.size());
  for (std::size_t v = 0; v < colour.size(); ++v)
    for (int k = 0; k < 3; ++k) out[3 * v + k] = static_cast<float>((colour[v] >> (21 * k)) & 0x1fffffu);
  return out;
}

void check_arrays(const PolygonMesh& m) {
  if (m.positions.size() % 3 != 0)
    throw Error(ErrorCode::kUsage, "polygon mesh: positions are not 3 per vertex");
  if (m.face_offsets.empty() || m.face_offsets[0] != 0 || m.face_offsets.back() != m.corners.size())
    throw Error(ErrorCode::kUsage, "polygon mesh: face offsets do not cover the corners");
  for (std::size_t f = 0; f + 1 < m.face_offsets.size(); ++f)
    if (m.face_offsets[f + 1] < m.face_offsets[f])
      throw Error(ErrorCode::kUsage, "polygon mesh: face offsets decrease at face " + std::to_string(f));
}

// A region with no quad vertex starts at the corners whose (vertex, next vertex) colours are smallest;
// canonical_regions compares the codes of the first kRegionTieCap of them only.
bool free_region_capped(const PolygonMesh& m, const QuadSubmesh& s,
                        const std::vector<std::uint64_t>& colour) {
  for (const NonQuadRegion& r : s.regions) {
    if (!r.loops.empty()) continue;
    std::pair<std::uint64_t, std::uint64_t> best{~0ull, ~0ull};
    std::uint64_t tied = 0;
    for (std::uint32_t f : r.faces) {
      const std::uint32_t b = m.face_offsets[f], d = m.degree(f);
      for (std::uint32_t i = 0; i < d; ++i) {
        // Bits as canonical_regions sees them: 63 of the 64 (colour_positions).
        const std::uint64_t mask = (std::uint64_t{1} << 63) - 1;
        const std::pair<std::uint64_t, std::uint64_t> k{colour[m.corners[b + i]] & mask,
                                                        colour[m.corners[b + (i + 1) % d]] & mask};
        if (k < best) best = k, tied = 0;
        tied += k == best;
      }
    }
    if (tied > kRegionTieCap) return true;
  }
  return false;
}

std::string degree_name(std::uint32_t d, std::uint64_t n) {
  const bool one = n == 1;
  if (d == 3) return one ? "triangle" : "triangles";
  if (d == 4) return one ? "quad" : "quads";
  return std::to_string(d) + (one ? "-gon" : "-gons");
}

// The first degree (increasing) whose face count differs: "A has 12 triangles, B has 10".
std::string degree_difference(const PolygonMatchInput& a, const PolygonMatchInput& b) {
  std::size_t i = 0, j = 0;
  while (i < a.degrees.size() || j < b.degrees.size()) {
    const std::uint32_t d =
        j == b.degrees.size() || (i < a.degrees.size() && a.degrees[i].first < b.degrees[j].first)
            ? a.degrees[i].first
            : b.degrees[j].first;
    const std::uint64_t na = i < a.degrees.size() && a.degrees[i].first == d ? a.degrees[i++].second : 0;
    const std::uint64_t nb = j < b.degrees.size() && b.degrees[j].first == d ? b.degrees[j++].second : 0;
    if (na != nb)
      return "A has " + std::to_string(na) + " " + degree_name(d, na) + ", B has " + std::to_string(nb) +
             " " + degree_name(d, nb);
  }
  return {};
}

std::string degree_list(const std::vector<std::uint32_t>& ds) {
  std::string s;
  for (std::size_t i = 0; i < ds.size() && i < 12; ++i) {
    if (i) s += ' ';
    s += std::to_string(ds[i]);
  }
  if (ds.size() > 12) s += " ...";
  return s;
}

std::uint32_t cut_vertex_count(const RegionCodes& c) {
  return static_cast<std::uint32_t>(c.glue_offsets.size() - 1);
}

// Empty when the region codes and glue are equal; else sets `level` and says why.
std::string region_difference(const RegionCodes& x, const RegionCodes& y, MatchLevel& level) {
  level = MatchLevel::kRegions;
  if (x.regions.size() != y.regions.size())
    return "A has " + std::to_string(x.regions.size()) + ", B has " + std::to_string(y.regions.size());
  for (std::size_t i = 0; i < x.regions.size(); ++i) {
    const RegionCode &p = x.regions[i], &q = y.regions[i];
    if (p == q) continue;
    const std::string which = "non-quad region " + std::to_string(i) + " (in canonical order)";
    if (p.degrees != q.degrees) {
      level = MatchLevel::kFaceDegrees;
      return which + ": A has faces of degrees " + degree_list(p.degrees) + ", B has " +
             degree_list(q.degrees);
    }
    if (p.start != q.start || p.loop != q.loop || p.position != q.position)
      return which + " lies at another place on the quads' holes";
    return which + ": its faces connect differently (same degrees)";
  }
  if (x.interior_vertices != y.interior_vertices)
    return "A has " + std::to_string(x.interior_vertices) + " vertices inside the regions, B has " +
           std::to_string(y.interior_vertices);
  level = MatchLevel::kGlue;
  if (cut_vertex_count(x) != cut_vertex_count(y))
    return "A has " + std::to_string(cut_vertex_count(x)) + " vertices cut into copies, B has " +
           std::to_string(cut_vertex_count(y));
  if (x.glue_offsets != y.glue_offsets || x.glue != y.glue) return "other copies are one vertex";
  level = MatchLevel::kNone;
  return {};
}

Vec3 centroid(const PolygonMesh& m) {
  Vec3 c{0, 0, 0};
  const std::size_t n = m.vertex_count();
  for (std::size_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) c[k] += m.positions[3 * v + k];
  if (n)
    for (int k = 0; k < 3; ++k) c[k] /= double(n);
  return c;
}

Vec3 relative(const PolygonMatchInput& p, std::uint32_t v, bool centered) {
  Vec3 x{p.mesh.positions[3 * std::size_t{v}], p.mesh.positions[3 * std::size_t{v} + 1],
         p.mesh.positions[3 * std::size_t{v} + 2]};
  if (centered)
    for (int k = 0; k < 3; ++k) x[k] -= p.centroid[k];
  return x;
}

// Sum over A's vertices of the squared distance to their images.
double cost(const PolygonMatchInput& a, const PolygonMatchInput& b, const std::vector<std::uint32_t>& vertex,
            bool centered) {
  double sum = 0;
  for (std::uint32_t v = 0; v < vertex.size(); ++v) {
    const Vec3 p = relative(a, v, centered), q = relative(b, vertex[v], centered);
    sum += (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
  }
  return sum;
}

std::vector<std::uint32_t> unreferenced(const PolygonMesh& m) {
  std::vector<std::uint8_t> used(m.vertex_count(), 0);
  for (std::uint32_t v : m.corners) used[v] = 1;
  std::vector<std::uint32_t> out;
  for (std::uint32_t v = 0; v < used.size(); ++v)
    if (!used[v]) out.push_back(v);
  return out;
}

// Each face as its corner list rotated to start at its smallest vertex, and that corner.
struct Normalized {
  std::vector<std::uint32_t> vertices;
  std::uint32_t face = 0, first = 0;
  bool operator<(const Normalized& o) const { return vertices < o.vertices; }
};

std::vector<Normalized> normalized_faces(const PolygonMesh& m) {
  std::vector<Normalized> out(m.face_count());
  for (std::uint32_t f = 0; f < out.size(); ++f) {
    const auto b = m.corners.begin() + m.face_offsets[f], e = m.corners.begin() + m.face_offsets[f + 1];
    const auto least = std::min_element(b, e);
    out[f].face = f;
    out[f].first = static_cast<std::uint32_t>(least - b);
    out[f].vertices.assign(least, e);
    out[f].vertices.insert(out[f].vertices.end(), b, least);
  }
  return out;
}

// The identity of vertex indices as an isomorphism A -> B, if it is one: the face map and rotations.
bool identity_match(const PolygonMesh& a, const PolygonMesh& b, PolygonMatchResult& r) {
  if (a.vertex_count() != b.vertex_count() || a.face_count() != b.face_count()) return false;
  const std::vector<Normalized> fa = normalized_faces(a);
  std::vector<Normalized> fb = normalized_faces(b);
  std::sort(fb.begin(), fb.end());
  std::vector<std::uint8_t> used(fb.size(), 0);
  r.face.assign(fa.size(), 0);
  r.rotation.assign(fa.size(), 0);
  for (const Normalized& x : fa) {
    auto it = std::lower_bound(fb.begin(), fb.end(), x);
    while (it != fb.end() && it->vertices == x.vertices && used[it - fb.begin()]) ++it;
    if (it == fb.end() || it->vertices != x.vertices) return false;
    used[it - fb.begin()] = 1;
    const auto d = static_cast<std::uint32_t>(x.vertices.size());
    r.face[x.face] = it->face;
    r.rotation[x.face] = (it->first + d - x.first) % d;
  }
  r.vertex.resize(a.vertex_count());
  std::iota(r.vertex.begin(), r.vertex.end(), 0u);
  return true;
}

// A's and B's canonical forms rebuild the same mesh (equal codes): the isomorphism A -> canonical -> B.
void compose(const PolygonMesh& a, const PolygonMesh& b, const CanonicalRegions& x, const CanonicalRegions& y,
             PolygonMatchResult& r) {
  const std::size_t nv = a.vertex_count(), nf = a.face_count();
  if (b.vertex_count() != nv || b.face_count() != nf || x.vertex.size() != nv || y.vertex.size() != nv ||
      x.face.size() != nf || y.face.size() != nf)
    throw Error(ErrorCode::kInternal, "match_polygons: equal codes for meshes of different sizes");
  std::vector<std::uint32_t> vb(nv, kInvalid), fb(nf, kInvalid);
  for (std::uint32_t v = 0; v < nv; ++v) vb[y.vertex[v]] = v;
  for (std::uint32_t f = 0; f < nf; ++f) fb[y.face[f]] = f;
  r.vertex.resize(nv);
  r.face.resize(nf);
  r.rotation.resize(nf);
  for (std::uint32_t v = 0; v < nv; ++v) r.vertex[v] = vb[x.vertex[v]];
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t g = fb[x.face[f]], d = a.degree(f);
    r.face[f] = g;
    r.rotation[f] = g == kInvalid ? 0 : (y.rotation[g] + d - x.rotation[f] % d) % d;
  }
}

PolygonMesh reversed(const PolygonMesh& m) {
  PolygonMesh out = m;
  for (std::size_t f = 0; f < m.face_count(); ++f)
    std::reverse(out.corners.begin() + m.face_offsets[f] + 1, out.corners.begin() + m.face_offsets[f + 1]);
  return out;
}

// How many vertices have each colour; a class of kSnapClass vertices at most is "small": its vertices
// are told apart one by one when a nearer isomorphism is looked for.
inline constexpr std::size_t kSnapClass = 64;

struct ClassSizes {
  std::vector<std::uint64_t> sorted;
  explicit ClassSizes(std::vector<std::uint64_t> colours) : sorted(std::move(colours)) {
    std::sort(sorted.begin(), sorted.end());
  }
  std::size_t size(std::uint64_t c) const {
    const auto [lo, hi] = std::equal_range(sorted.begin(), sorted.end(), c);
    return static_cast<std::size_t>(hi - lo);
  }
  bool small(std::uint64_t c) const {
    const std::size_t n = size(c);
    return n > 1 && n <= kSnapClass;
  }
};

std::uint64_t individual(std::uint64_t colour, std::uint32_t id) { return mix(colour ^ mix(id + 1ull)); }

// The canonical regions (codes and maps; no quads) of `m` with these vertex colours.
CanonicalRegions regions_with(const PolygonMesh& m, const std::vector<std::uint64_t>& colours) {
  const auto nv = static_cast<std::uint32_t>(m.vertex_count());
  const std::vector<float> at = colour_positions(colours);
  QuadSubmesh s = quad_submesh(m.face_offsets, m.corners, nv, at);
  CanonicalMesh q = canonicalize(s.mesh, s.adjacency, partition_motorcycle(s.adjacency));
  CanonicalRegions r = canonical_regions(m.face_offsets, m.corners, nv, at, s, std::move(q));
  r.quads = {};  // only its codes and maps are compared and composed
  return r;
}

// B's colours with each vertex of a small class told apart by the index of the nearest A vertex of its
// class (positions relative to the centroids unless `centered` is false), and each vertex of a larger
// class by the A vertex of its class at exactly its position, if any: where B is A moved a little (or
// renumbered), B's canonical form then agrees with A's `individual` one through the nearest
// isomorphism. O(V log V + kSnapClass V).
std::vector<std::uint64_t> snapped_colours(const PolygonMatchInput& a, const PolygonMatchInput& b,
                                           bool centered) {
  const ClassSizes sizes_a(a.colours);
  std::vector<std::uint32_t> order(a.colours.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
    return std::pair(a.colours[x], x) < std::pair(a.colours[y], y);
  });
  auto at = [](const PolygonMatchInput& m, std::uint32_t v) {
    std::array<std::uint32_t, 3> bits;
    std::memcpy(bits.data(), &m.mesh.positions[3 * std::size_t{v}], sizeof bits);
    return bits;
  };
  std::map<std::pair<std::uint64_t, std::array<std::uint32_t, 3>>, std::uint32_t> exact;  // large classes
  for (std::uint32_t v = 0; v < a.colours.size(); ++v)
    if (sizes_a.size(a.colours[v]) > kSnapClass) exact.emplace(std::pair(a.colours[v], at(a, v)), v);
  std::vector<std::uint64_t> out(b.colours);
  for (std::uint32_t w = 0; w < out.size(); ++w) {
    const std::uint64_t c = b.colours[w];
    if (sizes_a.size(c) > kSnapClass) {
      const auto it = exact.find(std::pair(c, at(b, w)));
      if (it != exact.end()) out[w] = individual(c, it->second);
      continue;
    }
    if (!sizes_a.small(c)) continue;
    const auto first = std::lower_bound(order.begin(), order.end(), c,
                                        [&](std::uint32_t v, std::uint64_t k) { return a.colours[v] < k; });
    const Vec3 q = relative(b, w, centered);
    double best = HUGE_VAL;
    std::uint32_t arg = *first;
    for (auto it = first; it != order.end() && a.colours[*it] == c; ++it) {
      const Vec3 p = relative(a, *it, centered);
      const double d =
          (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
      if (d < best) best = d, arg = *it;
    }
    out[w] = individual(c, arg);
  }
  return out;
}

PolygonMatchResult match_oriented(const PolygonMatchInput& a, const PolygonMatchInput& b,
                                  const MatchOptions& options, bool& could_mirror) {
  PolygonMatchResult r;
  auto differ = [&](MatchLevel level, const std::string& why) {
    r.level = level;
    r.reason = std::string(match_level_name(level)) + ": " + why;
    return r;
  };
  could_mirror = false;
  if (a.degrees != b.degrees) return differ(MatchLevel::kFaceDegrees, degree_difference(a, b));
  std::string why;
  const MatchLevel quad_level = detail::quad_difference(a.quads, b.quads, why);
  if (quad_level != MatchLevel::kNone) {
    could_mirror = quad_level == MatchLevel::kSchematic || quad_level == MatchLevel::kCode;
    return differ(quad_level, why + " (the quad submeshes)");
  }
  MatchLevel level = MatchLevel::kNone;
  why = region_difference(a.regions.codes, b.regions.codes, level);
  if (level != MatchLevel::kNone) {
    if (a.capped || b.capped)
      throw Error(ErrorCode::kUnsupported,
                  "cannot decide: a piece of non-quad faces with no quad is too symmetric for its canonical "
                  "code to be certain (more than " +
                      std::to_string(kRegionTieCap) + " tied starts); its " + why);
    could_mirror = true;
    return differ(level, why);
  }

  r.isomorphic = true;
  compose(a.mesh, b.mesh, a.regions, b.regions, r);
  r.unique = a.rigid;
  if (options.prefer_order && !a.rigid) {
    PolygonMatchResult same = r;
    if (!identity_match(a.mesh, b.mesh, same))
      throw Error(
          ErrorCode::kUnsupported,
          "--prefer-order: A has symmetries (or vertices its neighbourhoods do not tell apart) and the "
          "identity of indices is no isomorphism; the search keeping most vertices at their index is "
          "for all-quad meshes only");
    r = std::move(same);
    r.identity = r.unique = true;
  }

  // Unreferenced vertices: any pairing is an isomorphism; take the nearest (by index with prefer_order).
  const bool centered = options.centering != Centering::kNone;
  const std::vector<std::uint32_t> ua = unreferenced(a.mesh), ub = unreferenced(b.mesh);
  if (!r.identity && ua.size() > 1) {
    std::vector<Vec3> xs, ys;
    for (std::uint32_t v : ua) xs.push_back(relative(a, v, centered));
    for (std::uint32_t v : ub) ys.push_back(relative(b, v, centered));
    bool exhaustive = true;
    const std::vector<std::uint32_t> to =
        detail::pair_nearest(xs, ys, options.tie_tolerance, r.ambiguous, exhaustive);
    for (std::size_t k = 0; k < ua.size(); ++k) r.vertex[ua[k]] = ub[to[k]];
  }
  r.cost = cost(a, b, r.vertex, centered);
  // A symmetric mesh: B's canonical form with its vertices told apart by their nearest A vertices
  // agrees with A's own-index one through the nearest isomorphism when B is A moved a little (a
  // renumbered copy, a morph); that map is valid whenever the codes agree, and taken if nearer.
  if (!r.unique && a.individual && !b.colours.empty()) {
    const CanonicalRegions snapped = regions_with(b.mesh, snapped_colours(a, b, centered));
    if (snapped.codes == a.individual->codes) {
      PolygonMatchResult p = r;
      compose(a.mesh, b.mesh, *a.individual, snapped, p);
      p.cost = cost(a, b, p.vertex, centered);
      p.snapped = true;
      if (p.cost < r.cost) r = std::move(p);
    }
  }
  r.same_positions = cost(a, b, r.vertex, false) == 0;
  return r;
}

}  // namespace

PolygonMatchInput prepare_polygon_match(PolygonMesh mesh) {
  check_arrays(mesh);
  PolygonMatchInput in;
  in.mesh = std::move(mesh);
  const PolygonMesh& m = in.mesh;
  const auto nv = static_cast<std::uint32_t>(m.vertex_count());
  // quad_submesh checks every index first: the colours below index by vertex.
  (void)cut_manifold(m.face_offsets, m.corners, nv);
  const std::vector<std::uint64_t> colour = vertex_colours(m);
  const std::vector<float> positions = colour_positions(colour);
  QuadSubmesh s = quad_submesh(m.face_offsets, m.corners, nv, positions);
  in.counts = s.counts;
  in.capped = free_region_capped(m, s, colour);
  CanonicalMesh quads = canonicalize(s.mesh, s.adjacency, partition_motorcycle(s.adjacency));
  in.regions = canonical_regions(m.face_offsets, m.corners, nv, positions, s, std::move(quads));
  in.quads.mesh = std::move(s.mesh);
  in.quads.adjacency = std::move(s.adjacency);
  in.quads.canonical = std::move(in.regions.quads);
  in.regions.quads = {};

  std::vector<std::uint32_t> degrees(m.face_count());
  for (std::size_t f = 0; f < degrees.size(); ++f) degrees[f] = m.degree(f);
  std::sort(degrees.begin(), degrees.end());
  for (std::uint32_t d : degrees) {
    if (in.degrees.empty() || in.degrees.back().first != d) in.degrees.emplace_back(d, 0);
    ++in.degrees.back().second;
  }
  std::vector<std::uint64_t> used;
  std::vector<std::uint8_t> seen(nv, 0);
  for (std::uint32_t v : m.corners)
    if (!seen[v]) seen[v] = 1, used.push_back(colour[v]);
  in.rigid = distinct(used) == used.size();
  in.centroid = centroid(m);
  in.colours = colour;
  if (!in.rigid) {
    // The same canonical form with every vertex of a small colour class told apart by its own index:
    // the side a nearer isomorphism is looked for against (match_oriented).
    std::vector<std::uint64_t> own(colour);
    const ClassSizes sizes(colour);
    for (std::uint32_t v = 0; v < nv; ++v)
      if (sizes.size(colour[v]) > 1) own[v] = individual(colour[v], v);
    in.individual = std::make_shared<const CanonicalRegions>(regions_with(m, own));
  }
  return in;
}

PolygonMatchResult match_polygons(const PolygonMatchInput& a, const PolygonMatchInput& b,
                                  const MatchOptions& options) {
  bool could_mirror = false;
  PolygonMatchResult r = match_oriented(a, b, options, could_mirror);
  const PolygonMesh* target = &b.mesh;
  PolygonMesh flipped;
  if (!r.isomorphic && could_mirror && options.mirror != Mirror::kNo) {
    flipped = reversed(b.mesh);
    bool again = false;
    PolygonMatchResult m = match_oriented(a, prepare_polygon_match(flipped), options, again);
    if (m.isomorphic && options.mirror == Mirror::kAccept) {
      // Reversed corner k is B's corner (d - k) % d, k = (c + r) % d.
      for (std::size_t f = 0; f < m.face.size(); ++f) {
        const std::uint32_t d = a.mesh.degree(f);
        m.rotation[f] = (d - m.rotation[f]) % d;
      }
      m.mirrored = true;
      r = std::move(m);
    } else {
      r.mirror_would_match = m.isomorphic;
    }
  }
  if (r.isomorphic) {
    std::string why;
    if (!verify_polygon_match(a.mesh, *target, r, &why))
      throw Error(ErrorCode::kInternal, "match_polygons: the map found is no isomorphism: " + why);
  }
  return r;
}

bool verify_polygon_match(const PolygonMesh& a, const PolygonMesh& b, const PolygonMatchResult& m,
                          std::string* why) {
  auto fail = [&](std::string s) {
    if (why) *why = std::move(s);
    return false;
  };
  if (!m.isomorphic) return fail("not isomorphic");
  if (a.vertex_count() != b.vertex_count() || a.face_count() != b.face_count()) return fail("sizes differ");
  if (m.vertex.size() != a.vertex_count() || m.face.size() != a.face_count() ||
      m.rotation.size() != a.face_count())
    return fail("map sizes differ from A's");
  std::vector<std::uint8_t> seen(b.vertex_count(), 0);
  for (std::size_t v = 0; v < m.vertex.size(); ++v) {
    if (m.vertex[v] >= b.vertex_count() || seen[m.vertex[v]])
      return fail("vertex map not a bijection at " + std::to_string(v));
    seen[m.vertex[v]] = 1;
  }
  std::vector<std::uint8_t> fseen(b.face_count(), 0);
  for (std::size_t f = 0; f < m.face.size(); ++f) {
    const std::uint32_t g = m.face[f], d = a.degree(f);
    if (g >= b.face_count() || fseen[g]) return fail("face map not a bijection at " + std::to_string(f));
    fseen[g] = 1;
    if (b.degree(g) != d) return fail("face " + std::to_string(f) + " maps to a face of another degree");
    if (m.rotation[f] >= d) return fail("face " + std::to_string(f) + ": rotation out of range");
    for (std::uint32_t c = 0; c < d; ++c) {
      const std::uint32_t k = m.mirrored ? (m.rotation[f] + d - c) % d : (c + m.rotation[f]) % d;
      if (m.vertex[a.corners[a.face_offsets[f] + c]] != b.corners[b.face_offsets[g] + k])
        return fail("face " + std::to_string(f) + " corner " + std::to_string(c) + " does not map");
    }
  }
  return true;
}

PolygonMesh reorder_polygons_like(const PolygonMesh& in, const PolygonMatchResult& m) {
  if (!m.isomorphic)
    throw Error(ErrorCode::kUsage, "reorder_polygons_like: the meshes are not isomorphic: " + m.reason);
  PolygonRenumbering r;
  r.vertex_from = m.vertex;
  r.face_from = m.face;
  r.first = m.rotation;
  r.reverse = m.mirrored;
  try {
    return permute(in, r);
  } catch (const Error& e) {
    throw Error(ErrorCode::kUsage, std::string("reorder_polygons_like: ") + e.what());
  }
}

}  // namespace qsp
