// Half-edge adjacency from a quad array, in O(n), with the manifold and orientation checks.
#include "qsp/mesh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <barrier>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <thread>

#include "beside.h"
#include "face_sets.h"
#include "mesh_split.h"
#include "qsp/error.h"

namespace qsp {
namespace {

[[noreturn]] void fail(ErrorCode code, const std::string& message, std::int64_t face = -1) {
  throw Error(code, message, face);
}

std::string face_str(std::uint32_t f) { return "face " + std::to_string(f); }

// The steps of build_adjacency, shared by its one-thread and two-thread paths. Each takes a `report`
// for what makes the mesh invalid: the one-thread path throws the error naming the problem, the
// two-thread path only notes that there is one (and the one-thread path then runs to name it). A
// step that reports stops and returns false.
using Report = void (*)(ErrorCode, const std::string&, std::int64_t);
[[noreturn]] void throw_report(ErrorCode code, const std::string& message, std::int64_t face) {
  fail(code, message, face);
}

// The half-edge after interior half-edge h around its face.
std::uint32_t face_next(std::uint32_t h) { return (h & ~3u) | ((h + 1) & 3u); }

// The two endpoints of interior half-edge h, smaller first.
std::uint32_t lo(std::span<const std::uint32_t> q, std::uint32_t h) {
  return std::min(q[h], q[face_next(h)]);
}
std::uint32_t hi(std::span<const std::uint32_t> q, std::uint32_t h) {
  return std::max(q[h], q[face_next(h)]);
}

// Faces [f0, f1): indices in range, no vertex twice.
bool check_faces(std::span<const std::uint32_t> q, std::uint32_t nv, std::uint32_t f0, std::uint32_t f1,
                 Report report) {
  for (std::uint32_t f = f0; f < f1; ++f) {
    for (int i = 0; i < 4; ++i) {
      if (q[4 * f + i] >= nv) {
        report(ErrorCode::kBadIndex,
               face_str(f) + ": vertex index " + std::to_string(q[4 * f + i]) + " out of range (" +
                   std::to_string(nv) + " vertices)",
               f);
        return false;
      }
      for (int j = 0; j < i; ++j)
        if (q[4 * f + i] == q[4 * f + j]) {
          report(ErrorCode::kDegenerateFace,
                 face_str(f) + ": vertex " + std::to_string(q[4 * f + i]) + " appears twice", f);
          return false;
        }
    }
  }
  return true;
}

// Half-edges are grouped by their smaller endpoint (counting sort), then each small group is sorted by
// the larger endpoint: O(n log d) instead of a global sort or a hash map. Entries are (larger endpoint
// << 32 | half-edge), so the small per-vertex sorts compare plain integers.
// Counts the half-edges of faces [f0, f1) into count[lo + 1].
void count_buckets(std::span<const std::uint32_t> q, std::uint32_t f0, std::uint32_t f1,
                   std::uint32_t* count) {
  for (std::uint32_t h = 4 * f0; h < 4 * f1; ++h) ++count[lo(q, h) + 1];
}
// Puts the half-edges of faces [f0, f1) into their buckets, at fill[lo] onwards.
void fill_buckets(std::span<const std::uint32_t> q, std::uint32_t f0, std::uint32_t f1, std::uint32_t* fill,
                  std::uint64_t* bucket) {
  for (std::uint32_t h = 4 * f0; h < 4 * f1; ++h)
    bucket[fill[lo(q, h)]++] = (std::uint64_t{hi(q, h)} << 32) | h;
}

// Every slot of the buckets is written before it is read: no zeroing (0.6M of mh_base's instructions).
std::unique_ptr<std::uint64_t[]> new_buckets(std::uint32_t nh) {
  return std::unique_ptr<std::uint64_t[]>(new std::uint64_t[nh]);
}

// `adj.twin` for the interior half-edges, all kInvalid, with room for the exterior ones add_exterior
// appends on a mesh with a usual boundary (copying the twins to grow cost mh_base 0.3M instructions).
void new_twins(Adjacency& adj, std::uint32_t nh) {
  adj.twin.reserve(std::size_t{nh} + nh / 8);
  adj.twin.assign(nh, kInvalid);
}

// Pairs the half-edges of the buckets of vertices [v0, v1) into twins; those without one go to
// `boundary_he` (interior half-edges on the boundary).
bool match_buckets(std::span<const std::uint32_t> q, const std::uint32_t* start, std::uint64_t* bucket,
                   std::uint32_t v0, std::uint32_t v1, std::uint32_t* twin,
                   std::vector<std::uint32_t>& boundary_he, Report report) {
  for (std::uint32_t v = v0; v < v1; ++v) {
    if (start[v] == start[v + 1]) continue;  // no edge (and `bucket` may be empty: no b + 1 below)
    std::uint64_t *const b = bucket + start[v], *const e = bucket + start[v + 1];
    if (e - b <= 8) {
      for (auto i = b + 1; i < e; ++i) {  // insertion sort: buckets are tiny
        const std::uint64_t x = *i;
        auto j = i;
        for (; j > b && *(j - 1) > x; --j) *j = *(j - 1);
        *j = x;
      }
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
        if (q[h0] == q[h1]) {
          report(ErrorCode::kOrientation,
                 face_str(h0 / 4) + " and " + face_str(h1 / 4) + " traverse edge " + std::to_string(v) + "-" +
                     std::to_string(other) + " in the same direction (inconsistent orientation)",
                 h1 / 4);
          return false;
        }
        twin[h0] = h1;
        twin[h1] = h0;
      } else {
        report(ErrorCode::kNonManifold,
               "non-manifold edge " + std::to_string(v) + "-" + std::to_string(other) + " has " +
                   std::to_string(n) + " faces (first: " + face_str(h0 / 4) + ", " +
                   face_str(static_cast<std::uint32_t>(it[1]) / 4) + ", " +
                   face_str(static_cast<std::uint32_t>(it[2]) / 4) + ")",
               static_cast<std::uint32_t>(it[2]) / 4);
        return false;
      }
      it = run;
    }
  }
  return true;
}

// Exterior half-edges (one per boundary edge, running the other way, numbered in the order of their
// interior twins), each vertex's half-edge, the boundary flags. `adj.twin` holds the interior twins
// (kInvalid on the boundary); `boundary_he` is sorted. The origins are add_origins'.
bool add_exterior(std::span<const std::uint32_t> q, const std::vector<std::uint32_t>& boundary_he,
                  Adjacency& adj, Report report) {
  const std::uint32_t nv = adj.vertex_count, nh = 4 * adj.face_count;
  const std::uint32_t nb = static_cast<std::uint32_t>(boundary_he.size());
  adj.twin.resize(nh + nb);
  adj.vertex_halfedge.assign(nv, kInvalid);
  adj.boundary.assign(nv, 0);
  for (std::uint32_t i = 0; i < nb; ++i) {
    const std::uint32_t h = boundary_he[i], x = nh + i;
    adj.twin[h] = x;
    adj.twin[x] = h;
    const std::uint32_t v = q[face_next(h)];
    if (adj.boundary[v]) {
      report(ErrorCode::kNonManifold,
             "non-manifold vertex " + std::to_string(v) + ": its faces form more than one fan", h / 4);
      return false;
    }
    adj.boundary[v] = 1;
    adj.vertex_halfedge[v] = x;
  }
  // The exterior half-edge after x (v -> u) leaves u, and is u's only exterior half-edge.
  adj.exterior_next.resize(nb);
  for (std::uint32_t i = 0; i < nb; ++i) adj.exterior_next[i] = adj.vertex_halfedge[q[boundary_he[i]]];
  for (std::uint32_t h = 0; h < nh; ++h)
    if (adj.vertex_halfedge[q[h]] == kInvalid) adj.vertex_halfedge[q[h]] = h;
  return true;
}

// The origins: the corners, then the exterior half-edges' (the heads of their interior twins).
void add_origins(std::span<const std::uint32_t> q, const std::vector<std::uint32_t>& boundary_he,
                 Adjacency& adj) {
  adj.origin.reserve(q.size() + boundary_he.size());
  adj.origin.assign(q.begin(), q.end());
  for (std::uint32_t h : boundary_he) adj.origin.push_back(q[face_next(h)]);
}

// Per vertex: the face corners at it, which with its exterior half-edge (if on the boundary) are the
// half-edges leaving it.
std::vector<std::uint32_t> count_corners(std::span<const std::uint32_t> q, std::uint32_t nv) {
  std::vector<std::uint32_t> corners(nv, 0);
  for (std::uint32_t v : q) ++corners[v];
  return corners;
}

// Valence by rotation from vertex_halfedge; a vertex whose rotation misses some of its half-edges
// has several fans (non-manifold), e.g. two cones touching at their tips. With `corners`
// (count_corners') the first such vertex is reported. Without, only that there is one (the two-thread
// path, saving the count, 0.4M of mh_base's instructions): a rotation that closes covers only
// half-edges leaving its vertex, so the rotations then cover fewer than all, in all at most as many
// steps as there are half-edges.
bool add_valence(Adjacency& adj, const std::vector<std::uint32_t>* corners, Report report) {
  const std::uint32_t nv = adj.vertex_count;
  adj.valence.assign(nv, 0);
  std::uint32_t left = adj.halfedge_count();  // without `corners`: the half-edges not yet covered
  for (std::uint32_t v = 0; v < nv; ++v) {
    const std::uint32_t h0 = adj.vertex_halfedge[v];
    if (h0 == kInvalid) continue;
    const std::uint32_t most = corners ? (*corners)[v] + adj.boundary[v] : left;
    std::uint32_t n = 0, h = h0;
    if (adj.boundary[v]) {
      do {
        ++n;
        h = adj.rotate(h);
      } while (h != h0 && n <= most);
    } else {
      do {  // inside, every edge at v has two faces: a rotation without the test for exterior half-edges
        ++n;
        h = face_next(adj.twin[h]);
      } while (h != h0 && n <= most);
    }
    if (corners ? n != most : n > most) {
      report(ErrorCode::kNonManifold,
             "non-manifold vertex " + std::to_string(v) + ": its faces form more than one fan",
             adj.face(h0) != kInvalid ? adj.face(h0) : adj.face(adj.twin[h0]));
      return false;
    }
    left -= n;
    adj.valence[v] = n;
  }
  return corners || left == 0;
}

// Components of faces, numbered by their first face. From the matched buckets (twins are the runs of
// two), not the twins: the two-thread path runs this beside add_exterior, which writes twins.
void add_components(Adjacency& adj, const std::uint32_t* start, const std::uint64_t* bucket) {
  std::vector<std::uint32_t> first_face;
  const std::uint32_t nv = adj.vertex_count;
  adj.face_component = detail::label_joined_faces(
      adj.face_count,
      [&](auto join) {
        for (std::uint32_t v = 0; v < nv; ++v)
          for (std::uint32_t i = start[v]; i + 1 < start[v + 1]; ++i)
            if ((bucket[i] >> 32) == (bucket[i + 1] >> 32)) {
              join(static_cast<std::uint32_t>(bucket[i]) >> 2,
                   static_cast<std::uint32_t>(bucket[i + 1]) >> 2);
              ++i;
            }
      },
      first_face);
  adj.component_count = static_cast<std::uint32_t>(first_face.size());
  adj.component_faces.assign(adj.component_count, 0);
  for (std::uint32_t f = 0; f < adj.face_count; ++f) ++adj.component_faces[adj.face_component[f]];
}

Adjacency adjacency_one_thread(std::span<const std::uint32_t> q, std::uint32_t nv) {
  Adjacency adj;
  const auto nf = static_cast<std::uint32_t>(q.size() / 4);
  const std::uint32_t nh = 4 * nf;
  adj.vertex_count = nv;
  adj.face_count = nf;
  check_faces(q, nv, 0, nf, throw_report);
  std::vector<std::uint32_t> start(nv + 1, 0);
  count_buckets(q, 0, nf, start.data());
  for (std::uint32_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::unique_ptr<std::uint64_t[]> bucket = new_buckets(nh);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    fill_buckets(q, 0, nf, fill.data(), bucket.get());
  }
  new_twins(adj, nh);
  std::vector<std::uint32_t> boundary_he;  // interior half-edges without a twin
  match_buckets(q, start.data(), bucket.get(), 0, nv, adj.twin.data(), boundary_he, throw_report);
  std::sort(boundary_he.begin(), boundary_he.end());
  add_exterior(q, boundary_he, adj, throw_report);
  add_origins(q, boundary_he, adj);
  const std::vector<std::uint32_t> corners = count_corners(q, nv);
  add_valence(adj, &corners, throw_report);
  add_components(adj, start.data(), bucket.get());
  return adj;
}

}  // namespace

namespace detail {

std::optional<Adjacency> build_adjacency_two_threads(std::span<const std::uint32_t> q, std::uint32_t nv) {
  const auto nf = static_cast<std::uint32_t>(q.size() / 4);
  const std::uint32_t nh = 4 * nf, half_faces = nf / 2;
  Adjacency adj;
  adj.vertex_count = nv;
  adj.face_count = nf;
  std::atomic<bool> bad{false};
  const Report note = [](ErrorCode, const std::string&, std::int64_t) {};
  // Per thread: its faces' bucket counts, then its fill cursors; its vertices' boundary half-edges.
  std::array<std::vector<std::uint32_t>, 2> count;
  std::array<std::vector<std::uint32_t>, 2> boundary_he;
  std::vector<std::uint32_t> start(nv + 1, 0);
  std::unique_ptr<std::uint64_t[]> bucket = new_buckets(nh);
  new_twins(adj, nh);
  std::uint32_t mid_vertex = 0;  // vertices [0, mid) are matched by thread 0, the rest by thread 1
  std::barrier sync(2);
  // Each phase runs on both threads (t = 0 here, 1 on the helper) between barriers; the second thread
  // only ever writes what is its own (its counts, its buckets' slots, its vertices' twins).
  auto phases = [&](int t) {
    const std::uint32_t f0 = t == 0 ? 0 : half_faces, f1 = t == 0 ? half_faces : nf;
    auto phase = [&](auto&& work) {
      if (!bad.load(std::memory_order_relaxed)) {
        try {
          if (!work()) bad = true;
        } catch (...) {
          bad = true;  // e.g. out of memory: the one-thread path says it
        }
      }
      sync.arrive_and_wait();
    };
    phase([&] {
      if (!check_faces(q, nv, f0, f1, note)) return false;
      count[t].assign(nv + 1, 0);
      count_buckets(q, f0, f1, count[t].data());
      return true;
    });
    phase([&] {  // thread 0: bucket starts, and each thread's cursors into them; the split by vertices
      if (t == 1) return true;
      for (std::uint32_t v = 0; v < nv; ++v) {
        const std::uint32_t c0 = count[0][v + 1], c1 = count[1][v + 1];
        count[0][v] = start[v];
        count[1][v] = start[v] + c0;
        start[v + 1] = start[v] + c0 + c1;
      }
      mid_vertex =
          static_cast<std::uint32_t>(std::lower_bound(start.begin(), start.end(), nh / 2) - start.begin());
      mid_vertex = std::min(mid_vertex, nv);
      return true;
    });
    phase([&] {
      fill_buckets(q, f0, f1, count[t].data(), bucket.get());
      return true;
    });
    phase([&] {
      const std::uint32_t v0 = t == 0 ? 0 : mid_vertex, v1 = t == 0 ? mid_vertex : nv;
      return match_buckets(q, start.data(), bucket.get(), v0, v1, adj.twin.data(), boundary_he[t], note);
    });
    // Last, each writing only its own members: here the exterior half-edges (in the order of their
    // interior twins), the valences and the origins; on the helper the components (about 2.3M
    // instructions each on mh_base).
    if (bad.load(std::memory_order_relaxed)) return;
    try {
      if (t == 1) {
        add_components(adj, start.data(), bucket.get());
        return;
      }
      std::vector<std::uint32_t>& all = boundary_he[0];
      all.insert(all.end(), boundary_he[1].begin(), boundary_he[1].end());
      std::sort(all.begin(), all.end());
      if (!add_exterior(q, all, adj, note) || !add_valence(adj, nullptr, note)) bad = true;
      add_origins(q, all, adj);
    } catch (...) {
      bad = true;
    }
  };
  Helper helper;
  try {
    helper = start_beside([&phases] { phases(1); });
  } catch (const std::system_error&) {
    return std::nullopt;  // no thread to be had: the one-thread path
  }
  phases(0);
  helper.join();
  if (bad) return std::nullopt;
  return adj;
}

}  // namespace detail

Adjacency build_adjacency(const QuadMesh& mesh, unsigned threads) {
  if (mesh.positions.size() % 3 != 0) fail(ErrorCode::kUsage, "mesh arrays are not whole vertices/faces");
  if (mesh.vertex_count() > kMaxVertices)
    fail(ErrorCode::kLimit, "mesh too large: at most 2^29 - 1 faces and 2^31 - 1 vertices");
  return build_adjacency(mesh.quads, static_cast<std::uint32_t>(mesh.vertex_count()), threads);
}

void set_thread_limit(unsigned n) { detail::thread_limit.store(n, std::memory_order_relaxed); }

Adjacency build_adjacency(std::span<const std::uint32_t> q, std::uint32_t vertex_count, unsigned threads) {
  if (q.size() % 4 != 0) fail(ErrorCode::kUsage, "mesh arrays are not whole vertices/faces");
  if (q.size() / 4 > kMaxFaces || vertex_count > kMaxVertices)
    fail(ErrorCode::kLimit, "mesh too large: at most 2^29 - 1 faces and 2^31 - 1 vertices");
  const std::size_t nf = q.size() / 4;
  if (threads != 1 && (threads >= 2 || nf >= detail::kAdjacencyTwoThreadsFrom) && threads_allowed()) {
    if (std::optional<Adjacency> adj = detail::build_adjacency_two_threads(q, vertex_count))
      return std::move(*adj);
  }
  return adjacency_one_thread(q, vertex_count);
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
