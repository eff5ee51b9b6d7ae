// The manifold cut and the quad submesh of a polygon mesh, numbered, with its non-quad regions and the
// quad-submesh boundary loops they touch (qsp/submesh.h).
#include "qsp/submesh.h"

#include <string>

#include "polygon_fans.h"
#include "qsp/error.h"

namespace qsp {
namespace {

[[noreturn]] void internal(const std::string& what) {
  throw Error(ErrorCode::kInternal, "quad submesh: " + what + " (please report this mesh)");
}

}  // namespace

ManifoldCut cut_manifold(std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> corners,
                         std::uint32_t vertex_count) {
  const detail::PolygonFans fans = detail::polygon_fans(face_offsets, corners, vertex_count);
  ManifoldCut out;
  out.cut_edges = fans.cut_edges;
  out.copy_original.resize(vertex_count);
  for (std::uint32_t v = 0; v < vertex_count; ++v) out.copy_original[v] = v;
  // Fans are numbered by their first corner, so v's first fan is the one holding v's first corner.
  std::vector<std::uint32_t> fan_copy(fans.fan_vertex.size());
  std::vector<std::uint8_t> fans_of(vertex_count, 0);  // 0, 1, 2 = two or more
  for (std::uint32_t fan = 0; fan < fan_copy.size(); ++fan) {
    const std::uint32_t v = fans.fan_vertex[fan];
    if (fans_of[v] == 0) {
      fan_copy[fan] = v;
    } else {
      fan_copy[fan] = static_cast<std::uint32_t>(out.copy_original.size());
      out.copy_original.push_back(v);
    }
    if (fans_of[v] == 1) ++out.cut_vertices;
    if (fans_of[v] < 2) ++fans_of[v];
  }
  out.corners.resize(corners.size());
  for (std::size_t c = 0; c < corners.size(); ++c) out.corners[c] = fan_copy[fans.corner_fan[c]];
  return out;
}

QuadSubmesh quad_submesh(std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> corners,
                         std::uint32_t vertex_count, std::span<const float> positions) {
  const detail::PolygonFans fans = detail::polygon_fans(face_offsets, corners, vertex_count);
  if (!positions.empty() && positions.size() != 3 * std::size_t{vertex_count})
    internal("positions are not 3 per vertex");
  const auto n = static_cast<std::uint32_t>(corners.size());
  const auto nf = static_cast<std::uint32_t>(face_offsets.size() - 1);
  auto degree = [&](std::uint32_t f) { return face_offsets[f + 1] - face_offsets[f]; };
  QuadSubmesh out;

  // Submesh vertices: per original vertex the quad fan of its first quad corner (or the vertex itself
  // if no face uses it), then the other quad fans by first corner, then the quad-less fans.
  const std::size_t nqf = fans.qfan_vertex.size();
  std::vector<std::uint32_t> qfan_index(nqf, kInvalid), first_qfan(vertex_count, kInvalid);
  std::vector<std::uint8_t> used(vertex_count, 0);
  for (std::uint32_t c = 0; c < n; ++c) {
    used[corners[c]] = 1;
    if (degree(fans.face_of[c]) == 4 && first_qfan[corners[c]] == kInvalid)
      first_qfan[corners[c]] = fans.corner_qfan[c];
  }
  auto& original = out.vertex_original;
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    if (first_qfan[v] != kInvalid) qfan_index[first_qfan[v]] = static_cast<std::uint32_t>(original.size());
    if (first_qfan[v] != kInvalid || !used[v]) original.push_back(v);
  }
  for (std::uint32_t c = 0; c < n; ++c) {
    if (degree(fans.face_of[c]) != 4 || qfan_index[fans.corner_qfan[c]] != kInvalid) continue;
    qfan_index[fans.corner_qfan[c]] = static_cast<std::uint32_t>(original.size());
    original.push_back(corners[c]);
  }
  const auto nq_vertices = static_cast<std::uint32_t>(original.size());
  std::vector<std::uint32_t> fan_interior(fans.fan_vertex.size(), kInvalid);
  for (std::uint32_t fan = 0; fan < fan_interior.size(); ++fan) {
    if (fans.fan_quad[fan]) continue;
    fan_interior[fan] = static_cast<std::uint32_t>(original.size());
    original.push_back(fans.fan_vertex[fan]);
  }
  out.corner_vertex.resize(n);
  for (std::uint32_t c = 0; c < n; ++c)
    out.corner_vertex[c] =
        fans.corner_qfan[c] != kInvalid ? qfan_index[fans.corner_qfan[c]] : fan_interior[fans.corner_fan[c]];

  // The quads, in input order with their corners as given.
  auto& counts = out.counts;
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t d = degree(f);
    if (d == 3) ++counts.triangles;
    if (d > 4) ++counts.ngons;
    if (d != 4) continue;
    ++counts.quads;
    out.quad_face.push_back(f);
    for (std::uint32_t c = face_offsets[f]; c < face_offsets[f + 1]; ++c)
      out.mesh.quads.push_back(out.corner_vertex[c]);
  }
  out.mesh.positions.assign(3 * std::size_t{nq_vertices}, 0.0f);
  if (!positions.empty())
    for (std::uint32_t i = 0; i < nq_vertices; ++i)
      for (int k = 0; k < 3; ++k) out.mesh.positions[3 * i + k] = positions[3 * std::size_t{original[i]} + k];
  counts.cut_edges = fans.cut_edges;
  counts.extra_copies = static_cast<std::uint32_t>(original.size() - vertex_count);
  {
    std::vector<std::uint8_t> copies(vertex_count, 0);  // 0, 1, 2 = two or more
    for (std::uint32_t v : original) {
      if (copies[v] == 1) ++counts.cut_vertices;
      if (copies[v] < 2) ++copies[v];
    }
  }

  try {
    out.adjacency = build_adjacency(out.mesh);
  } catch (const Error& e) {
    internal(e.what());
  }
  const Adjacency& adj = out.adjacency;

  // Boundary loops, numbered by their smallest exterior half-edge.
  const std::uint32_t first_exterior = 4 * adj.face_count, nh = adj.halfedge_count();
  out.exterior_loop.assign(nh - first_exterior, kInvalid);
  for (std::uint32_t x = first_exterior; x < nh; ++x) {
    if (out.exterior_loop[x - first_exterior] != kInvalid) continue;
    const auto id = static_cast<std::uint32_t>(out.loop_halfedge.size());
    out.loop_halfedge.push_back(x);
    std::uint32_t y = x;
    do {
      if (out.exterior_loop[y - first_exterior] != kInvalid) internal("boundary loop does not close");
      out.exterior_loop[y - first_exterior] = id;
      y = adj.exterior_next[y - first_exterior];
    } while (y != x);
  }
  auto loop_of = [&](std::uint32_t qfan) {
    const std::uint32_t h = adj.vertex_halfedge[qfan_index[qfan]];
    if (h == kInvalid || !adj.is_exterior(h)) internal("a non-quad face touches an inner quad vertex");
    return out.exterior_loop[h - first_exterior];
  };

  // Regions: non-quad faces flooded across glued edges, numbered by their smallest face.
  std::vector<std::uint32_t> region(nf, kInvalid), stack;
  std::uint32_t nr = 0;
  for (std::uint32_t f0 = 0; f0 < nf; ++f0) {
    if (degree(f0) == 4 || region[f0] != kInvalid) continue;
    region[f0] = nr;
    stack.push_back(f0);
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      for (std::uint32_t c = face_offsets[f]; c < face_offsets[f + 1]; ++c) {
        if (fans.twin[c] == kInvalid) continue;
        const std::uint32_t g = fans.face_of[fans.twin[c]];
        if (degree(g) == 4 || region[g] != kInvalid) continue;
        region[g] = nr;
        stack.push_back(g);
      }
    }
    ++nr;
  }
  out.regions.resize(nr);
  for (std::uint32_t f = 0; f < nf; ++f)
    if (region[f] != kInvalid) out.regions[region[f]].faces.push_back(f);
  // Interior vertices: fans are numbered by first corner, so these come out increasing.
  {
    std::vector<std::uint8_t> listed(fans.fan_vertex.size(), 0);
    for (std::uint32_t c = 0; c < n; ++c) {
      const std::uint32_t fan = fans.corner_fan[c];
      if (fans.fan_quad[fan] || listed[fan]) continue;
      listed[fan] = 1;
      out.regions[region[fans.face_of[c]]].interior.push_back(fan_interior[fan]);
    }
  }
  // Loops: the (region, loop) pairs once each, region by region, then handed out in loop order (a
  // counting sort, so a region touching many loops costs no comparison sort).
  {
    std::vector<std::uint32_t> stamp(out.loop_halfedge.size(), kInvalid);
    std::vector<std::uint32_t> pair_region, pair_loop;
    for (std::uint32_t r = 0; r < nr; ++r)
      for (std::uint32_t f : out.regions[r].faces)
        for (std::uint32_t c = face_offsets[f]; c < face_offsets[f + 1]; ++c)
          for (std::uint32_t q : {fans.corner_qfan[c], fans.corner_qfan_other[c]}) {
            if (q == kInvalid) continue;
            const std::uint32_t loop = loop_of(q);
            if (stamp[loop] == r) continue;
            stamp[loop] = r;
            pair_region.push_back(r);
            pair_loop.push_back(loop);
          }
    std::vector<std::uint32_t> start(out.loop_halfedge.size() + 1, 0), order(pair_loop.size());
    for (std::uint32_t loop : pair_loop) ++start[loop + 1];
    for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
    for (std::uint32_t i = 0; i < pair_loop.size(); ++i) order[start[pair_loop[i]]++] = i;
    for (std::uint32_t i : order) out.regions[pair_region[i]].loops.push_back(pair_loop[i]);
  }
  return out;
}

PolygonMesh polygon_mesh(QuadMesh mesh) {
  PolygonMesh out;
  out.positions = std::move(mesh.positions);
  out.face_offsets.resize(mesh.quads.size() / 4 + 1);
  for (std::size_t f = 0; f < out.face_offsets.size(); ++f)
    out.face_offsets[f] = static_cast<std::uint32_t>(4 * f);
  out.corners = std::move(mesh.quads);
  return out;
}

}  // namespace qsp
