// The non-quad regions seen from the quad submesh: reverse half-edges within regions, hole edges
// glued to them, and the copies of each input vertex (src/region_coder.h).
#include "region_coder.h"

#include <algorithm>

#include "qsp/error.h"

namespace qsp::detail {

void regions_internal(const std::string& what) {
  throw Error(ErrorCode::kInternal, "regions: " + what + " (please report this mesh)");
}

RegionFaces region_faces(std::span<const std::uint32_t> offsets, const QuadSubmesh& s) {
  RegionFaces out;
  out.offsets = offsets;
  out.vertex = s.corner_vertex;
  out.layout_vertices = static_cast<std::uint32_t>(s.mesh.vertex_count());
  const auto nf = static_cast<std::uint32_t>(offsets.size() - 1);
  const auto n = static_cast<std::uint32_t>(s.corner_vertex.size());
  const auto ids = static_cast<std::uint32_t>(s.vertex_original.size());
  out.face_of.resize(n);
  for (std::uint32_t f = 0; f < nf; ++f)
    for (std::uint32_t c = offsets[f]; c < offsets[f + 1]; ++c) out.face_of[c] = f;
  out.region_of.assign(nf, kInvalid);
  for (std::uint32_t r = 0; r < s.regions.size(); ++r)
    for (std::uint32_t f : s.regions[r].faces) out.region_of[f] = r;

  const Adjacency& adj = s.adjacency;
  out.loop_next.assign(ids, kInvalid);
  out.loop_prev.assign(ids, kInvalid);
  out.hole_loop.assign(ids, kInvalid);
  for (std::uint32_t h = 4 * adj.face_count; h < adj.halfedge_count(); ++h) {
    const std::uint32_t u = adj.origin[h], w = adj.origin[adj.twin[h]];
    out.loop_next[u] = w;
    out.loop_prev[w] = u;
    out.hole_loop[u] = s.exterior_loop[h - 4 * adj.face_count];
  }
  out.loop_length.assign(s.loop_halfedge.size(), 0);
  for (std::uint32_t l : s.exterior_loop) ++out.loop_length[l];

  // Reverse half-edges within regions: half-edges sorted by (low, high) end with two counting sorts.
  std::vector<std::uint32_t> half;  // region corners
  for (std::uint32_t c = 0; c < n; ++c)
    if (out.region_of[out.face_of[c]] != kInvalid) half.push_back(c);
  auto lo = [&](std::uint32_t c) { return std::min(out.vertex[c], out.vertex[out.next(c)]); };
  auto hi = [&](std::uint32_t c) { return std::max(out.vertex[c], out.vertex[out.next(c)]); };
  std::vector<std::uint32_t> count(ids + 1), sorted(half.size());
  auto counting_sort = [&](auto key) {
    std::fill(count.begin(), count.end(), 0);
    for (std::uint32_t c : half) ++count[key(c) + 1];
    for (std::uint32_t i = 1; i <= ids; ++i) count[i] += count[i - 1];
    for (std::uint32_t c : half) sorted[count[key(c)]++] = c;
    half.swap(sorted);
  };
  counting_sort(hi);
  counting_sort(lo);
  out.twin.assign(n, kInvalid);
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i + 1;
    while (j < half.size() && lo(half[j]) == lo(half[i]) && hi(half[j]) == hi(half[i])) ++j;
    const std::uint32_t a = half[i], b = half[i + 1 < j ? i + 1 : i];
    if (j - i == 2 && out.vertex[a] != out.vertex[b] &&
        out.region_of[out.face_of[a]] == out.region_of[out.face_of[b]]) {
      out.twin[a] = b;
      out.twin[b] = a;
    }
    i = j;
  }
  // A region edge u -> w glued in the input to a quad ends on that quad's copy of w (rule 4 turns
  // counter-clockwise from the face at w, across this edge), whose hole edge out of w goes to the quad's
  // copy of u: matched when that is a copy of u, whichever copy rule 4 gave the face at u.
  out.anchor.assign(n, kInvalid);
  for (std::uint32_t c : half) {
    const std::uint32_t w = out.vertex[out.next(c)];
    const std::uint32_t u = w < out.layout_vertices ? out.loop_prev[w] : kInvalid;
    if (u != kInvalid && s.vertex_original[u] == s.vertex_original[out.vertex[c]]) out.anchor[c] = u;
  }
  return out;
}

GlueGroups glue_groups(const QuadSubmesh& s, std::uint32_t vertex_count) {
  std::vector<std::uint32_t> start(vertex_count + 1, 0), copies(s.vertex_original.size());
  for (std::uint32_t v : s.vertex_original) ++start[v + 1];
  for (std::uint32_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::uint32_t c = 0; c < s.vertex_original.size(); ++c) copies[fill[s.vertex_original[c]]++] = c;
  GlueGroups g;
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    if (start[v + 1] - start[v] < 2) continue;
    g.members.insert(g.members.end(), copies.begin() + start[v], copies.begin() + start[v + 1]);
    g.offsets.push_back(static_cast<std::uint32_t>(g.members.size()));
  }
  return g;
}

}  // namespace qsp::detail
