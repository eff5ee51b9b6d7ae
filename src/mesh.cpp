// Half-edge adjacency from a quad array, in O(n), with the manifold and orientation checks.
#include "qsp/mesh.h"

#include <algorithm>
#include <string>

#include "face_sets.h"
#include "qsp/error.h"

namespace qsp {
namespace {

[[noreturn]] void fail(ErrorCode code, const std::string& message, std::int64_t face = -1) {
  throw Error(code, message, face);
}

std::string face_str(std::uint32_t f) { return "face " + std::to_string(f); }

}  // namespace

Adjacency build_adjacency(const QuadMesh& mesh) {
  if (mesh.positions.size() % 3 != 0) fail(ErrorCode::kUsage, "mesh arrays are not whole vertices/faces");
  if (mesh.vertex_count() > kMaxVertices)
    fail(ErrorCode::kLimit, "mesh too large: at most 2^29 - 1 faces and 2^31 - 1 vertices");
  return build_adjacency(mesh.quads, static_cast<std::uint32_t>(mesh.vertex_count()));
}

Adjacency build_adjacency(std::span<const std::uint32_t> q, std::uint32_t vertex_count) {
  if (q.size() % 4 != 0) fail(ErrorCode::kUsage, "mesh arrays are not whole vertices/faces");
  if (q.size() / 4 > kMaxFaces || vertex_count > kMaxVertices)
    fail(ErrorCode::kLimit, "mesh too large: at most 2^29 - 1 faces and 2^31 - 1 vertices");
  Adjacency adj;
  const std::uint32_t nv = vertex_count;
  const auto nf = static_cast<std::uint32_t>(q.size() / 4);
  const std::uint32_t nh = 4 * nf;
  adj.vertex_count = nv;
  adj.face_count = nf;

  for (std::uint32_t f = 0; f < nf; ++f) {
    for (int i = 0; i < 4; ++i) {
      if (q[4 * f + i] >= nv)
        fail(ErrorCode::kBadIndex,
             face_str(f) + ": vertex index " + std::to_string(q[4 * f + i]) + " out of range (" +
                 std::to_string(nv) + " vertices)",
             f);
      for (int j = 0; j < i; ++j)
        if (q[4 * f + i] == q[4 * f + j])
          fail(ErrorCode::kDegenerateFace,
               face_str(f) + ": vertex " + std::to_string(q[4 * f + i]) + " appears twice", f);
    }
  }

  // Group half-edges by their smaller endpoint (counting sort), then sort each small group by the
  // larger endpoint: O(n log d) instead of a global sort or a hash map.
  std::vector<std::uint32_t> start(nv + 1, 0);
  auto lo = [&](std::uint32_t h) { return std::min(q[h], q[(h & ~3u) | ((h + 1) & 3u)]); };
  auto hi = [&](std::uint32_t h) { return std::max(q[h], q[(h & ~3u) | ((h + 1) & 3u)]); };
  for (std::uint32_t h = 0; h < nh; ++h) ++start[lo(h) + 1];
  for (std::uint32_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  // Entries: (larger endpoint << 32 | half-edge), so the small per-vertex sorts compare plain integers.
  std::vector<std::uint64_t> bucket(nh);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t h = 0; h < nh; ++h) bucket[fill[lo(h)]++] = (std::uint64_t{hi(h)} << 32) | h;
  }
  adj.twin.assign(nh, kInvalid);
  std::vector<std::uint32_t> boundary_he;  // interior half-edges without a twin
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (start[v] == start[v + 1]) continue;  // no edge (and `bucket` may be empty: no b + 1 below)
    const auto b = bucket.begin() + start[v], e = bucket.begin() + start[v + 1];
    if (e - b <= 8) {
      for (auto i = b + 1; i < e; ++i)  // insertion sort: buckets are tiny
        for (auto j = i; j > b && *(j - 1) > *j; --j) std::swap(*(j - 1), *j);
    } else {
      std::sort(b, e);
    }
    for (auto it = b; it != e;) {
      auto run = it;
      while (run != e && (*run >> 32) == (*it >> 32)) ++run;
      const auto n = run - it;
      const std::uint32_t h0 = static_cast<std::uint32_t>(*it), other = static_cast<std::uint32_t>(*it >> 32);
      if (n == 1) {
        boundary_he.push_back(h0);
      } else if (n == 2) {
        const std::uint32_t h1 = static_cast<std::uint32_t>(it[1]);
        if (q[h0] == q[h1])
          fail(ErrorCode::kOrientation,
               face_str(h0 / 4) + " and " + face_str(h1 / 4) + " traverse edge " + std::to_string(v) + "-" +
                   std::to_string(other) + " in the same direction (inconsistent orientation)",
               h1 / 4);
        adj.twin[h0] = h1;
        adj.twin[h1] = h0;
      } else {
        fail(ErrorCode::kNonManifold,
             "non-manifold edge " + std::to_string(v) + "-" + std::to_string(other) + " has " +
                 std::to_string(n) + " faces (first: " + face_str(h0 / 4) + ", " +
                 face_str(static_cast<std::uint32_t>(it[1]) / 4) + ", " +
                 face_str(static_cast<std::uint32_t>(it[2]) / 4) + ")",
             static_cast<std::uint32_t>(it[2]) / 4);
      }
      it = run;
    }
  }
  bucket.clear();
  bucket.shrink_to_fit();

  // Exterior half-edges: one per boundary edge, running the other way.
  const std::uint32_t nb = static_cast<std::uint32_t>(boundary_he.size());
  std::sort(boundary_he.begin(), boundary_he.end());
  adj.twin.resize(nh + nb);
  adj.origin.resize(nh + nb);
  for (std::uint32_t h = 0; h < nh; ++h) adj.origin[h] = q[h];
  adj.vertex_halfedge.assign(nv, kInvalid);
  adj.boundary.assign(nv, 0);
  for (std::uint32_t i = 0; i < nb; ++i) {
    const std::uint32_t h = boundary_he[i], x = nh + i;
    adj.twin[h] = x;
    adj.twin[x] = h;
    const std::uint32_t v = q[(h & ~3u) | ((h + 1) & 3u)];
    adj.origin[x] = v;
    if (adj.boundary[v])
      fail(ErrorCode::kNonManifold,
           "non-manifold vertex " + std::to_string(v) + ": its faces form more than one fan", h / 4);
    adj.boundary[v] = 1;
    adj.vertex_halfedge[v] = x;
  }
  // The exterior half-edge after x (v -> u) leaves u, and is u's only exterior half-edge.
  adj.exterior_next.resize(nb);
  for (std::uint32_t i = 0; i < nb; ++i) adj.exterior_next[i] = adj.vertex_halfedge[q[boundary_he[i]]];
  for (std::uint32_t h = 0; h < nh; ++h)
    if (adj.vertex_halfedge[q[h]] == kInvalid) adj.vertex_halfedge[q[h]] = h;

  // Valence by rotation from vertex_halfedge; a vertex whose rotation misses some of its half-edges
  // has several fans (non-manifold), e.g. two cones touching at their tips.
  std::vector<std::uint32_t> outgoing(nv, 0);
  for (std::uint32_t h = 0; h < nh + nb; ++h) ++outgoing[adj.origin[h]];
  adj.valence.assign(nv, 0);
  for (std::uint32_t v = 0; v < nv; ++v) {
    const std::uint32_t h0 = adj.vertex_halfedge[v];
    if (h0 == kInvalid) continue;
    std::uint32_t n = 0, h = h0;
    do {
      ++n;
      h = adj.rotate(h);
    } while (h != h0 && n <= outgoing[v]);
    if (n != outgoing[v])
      fail(ErrorCode::kNonManifold,
           "non-manifold vertex " + std::to_string(v) + ": its faces form more than one fan",
           adj.face(h0) != kInvalid ? adj.face(h0) : adj.face(adj.twin[h0]));
    adj.valence[v] = n;
  }

  // Components of faces, numbered by their first face.
  std::vector<std::uint32_t> first_face;
  adj.face_component = detail::label_face_sets(
      nf, adj.twin, [](std::uint32_t) { return true; }, first_face);
  adj.component_count = static_cast<std::uint32_t>(first_face.size());
  adj.component_faces.assign(adj.component_count, 0);
  for (std::uint32_t f = 0; f < nf; ++f) ++adj.component_faces[adj.face_component[f]];
  return adj;
}

std::vector<ComponentInfo> component_info(const Adjacency& adj) {
  std::vector<ComponentInfo> info(adj.component_count);
  for (std::uint32_t f = 0; f < adj.face_count; ++f) ++info[adj.face_component[f]].faces;
  for (std::uint32_t h = 0; h < adj.halfedge_count(); ++h) {
    if (adj.is_exterior(h)) continue;
    auto& c = info[adj.face_component[h >> 2]];
    const std::uint32_t t = adj.twin[h];
    if (adj.is_exterior(t)) {
      ++c.edges;
      ++c.boundary_edges;
    } else if (h < t) {
      ++c.edges;
    }
  }
  for (std::uint32_t v = 0; v < adj.vertex_count; ++v) {
    const std::uint32_t h = adj.vertex_halfedge[v];
    if (h == kInvalid) continue;
    auto& c = info[adj.face_component[adj.face(h) != kInvalid ? adj.face(h) : adj.face(adj.twin[h])]];
    ++c.vertices;
    c.deficiency_sum += adj.deficiency(v);
    if (adj.extraordinary(v)) ++c.extraordinary;
  }
  return info;
}

std::vector<std::uint32_t> extraordinary_vertices(const Adjacency& adj) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t v = 0; v < adj.vertex_count; ++v)
    if (adj.extraordinary(v)) out.push_back(v);
  return out;
}

}  // namespace qsp
