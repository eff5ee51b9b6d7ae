// From a schematic to the mesh it stands for (grid_layout), the link back to the input mesh
// (layout_to_mesh), and the checks of §4's definition (validate).
#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <queue>
#include <span>
#include <string>

#include "layout_grid.h"
#include "qsp/error.h"
#include "qsp/partition.h"

namespace qsp {
namespace {

std::uint32_t right_of(const Adjacency& adj, std::uint32_t h) { return adj.next(adj.twin[adj.next(h)]); }
std::uint32_t up_of(const Adjacency& adj, std::uint32_t h) { return adj.twin[adj.next(adj.next(h))]; }

// Visits the a x b cells of one grid, row by row, with their corner ids (from the point rows that
// fill_row(j, out) writes, a + 1 ids each) and, when adj is given, the mesh half-edge at their bottom,
// walked from `h`. Returns false when `visit` does (it stops the walk).
template <class FillRow, class Visit>
bool for_each_grid_cell(std::uint32_t a, std::uint32_t b, const Adjacency* adj, std::uint32_t h,
                        std::vector<std::uint32_t>& rows, FillRow&& fill_row, Visit& visit) {
  if (a == 0 || b == 0) return true;
  rows.resize(2 * (std::size_t{a} + 1));
  std::uint32_t *lo = rows.data(), *hi = lo + a + 1;
  fill_row(0, lo);
  std::uint32_t c[4];
  for (std::uint32_t j = 0; j < b; ++j) {
    fill_row(j + 1, hi);
    std::uint32_t g = h;
    for (std::uint32_t i = 0; i < a; ++i) {
      c[0] = lo[i], c[1] = lo[i + 1], c[2] = hi[i + 1], c[3] = hi[i];
      if (!visit(c, g)) return false;
      if (adj && i + 1 < a) g = right_of(*adj, g);
    }
    if (adj && j + 1 < b) h = up_of(*adj, h);
    std::swap(lo, hi);
  }
  return true;
}

// Visits every cell of the layout with its layout corner ids and (when adj given) the mesh half-edge
// at its bottom; returns false from `visit` to stop. The points go row by row, not through
// PatchGrid::at and its tests of which side a point is on (they were most of grid_layout's time).
template <class Visit>
void for_each_cell(const ComponentPartition& part, const Numbering* n, const Adjacency* adj, Visit&& visit) {
  std::vector<std::uint32_t> rows;
  if (part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus) {
    const std::uint32_t a = part.a, b = part.b;
    const bool torus = part.kind == ComponentKind::kTorus;
    auto fill_row = [&](std::uint32_t y, std::uint32_t* out) {
      for (std::uint32_t x = 0; x < a; ++x) out[x] = torus && y == b ? (x + part.twist) % a : y * a + x;
      out[a] = out[0];
    };
    for_each_grid_cell(a, b, adj, adj ? part.anchor_halfedge : kInvalid, rows, fill_row, visit);
    return;
  }
  const Schematic& s = part.schematic;
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    const PatchGrid& g = n->patches[f];
    auto fill_row = [&g](std::uint32_t j, std::uint32_t* out) { g.row(j, out); };
    if (!for_each_grid_cell(g.a, g.b, adj, adj ? s.dart_halfedge[s.face_dart[f]] : kInvalid, rows, fill_row,
                            visit))
      return;
  }
}

std::uint32_t layout_vertex_count(const ComponentPartition& part, const Numbering& n) {
  if (part.kind == ComponentKind::kAnnulus) return part.a * (part.b + 1);
  if (part.kind == ComponentKind::kTorus) return part.a * part.b;
  return n.vertex_count;
}

std::uint64_t layout_face_count(const ComponentPartition& part, const Numbering& n) {
  if (part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus)
    return std::uint64_t{part.a} * part.b;
  std::uint64_t faces = 0;
  for (const PatchGrid& g : n.patches) faces += std::uint64_t{g.a} * g.b;
  return faces;
}

// Layout -> mesh correspondence; returns why it fails, or empty.
std::string link(const ComponentPartition& part, const Adjacency& adj, LayoutMap& map) {
  Numbering n;
  if (part.kind == ComponentKind::kUnstructured || part.kind == ComponentKind::kDisk) {
    std::string why = number_schematic(part.schematic, n);
    if (!why.empty()) return why;
  }
  map.vertex.assign(layout_vertex_count(part, n), kInvalid);
  map.face.clear();
  map.rotation.clear();
  // No more than the component holds: a wrong partition's walk stops where it leaves the component.
  map.face.reserve(std::min<std::uint64_t>(layout_face_count(part, n), adj.component_faces[part.component]));
  map.rotation.reserve(map.face.capacity());
  // The messages are built after the walk, so that the visit stays small enough to inline.
  std::uint32_t* const vertex = map.vertex.data();
  std::uint32_t clash[2] = {kInvalid, kInvalid};
  bool left = false;
  for_each_cell(part, &n, &adj, [&](const std::uint32_t* c, std::uint32_t h) {
    const std::uint32_t f = adj.face(h);
    if (f == kInvalid || adj.face_component[f] != part.component) {
      left = true;
      return false;
    }
    map.face.push_back(f);
    map.rotation.push_back(static_cast<std::uint8_t>(h & 3));
    // Grid corner k is the face's corner h + k. A point already set is mostly set to the same vertex.
    const std::uint32_t* const corner = &adj.origin[h & ~3u];
    auto put = [&](std::uint32_t point, std::uint32_t mv) {
      std::uint32_t& slot = vertex[point];
      if (slot == mv) return true;
      if (slot != kInvalid) {
        clash[0] = slot, clash[1] = mv;
        return false;
      }
      slot = mv;
      return true;
    };
    return put(c[0], corner[h & 3u]) && put(c[1], corner[(h + 1) & 3u]) && put(c[2], corner[(h + 2) & 3u]) &&
           put(c[3], corner[(h + 3) & 3u]);
  });
  std::string why;
  if (left) {
    why = "grid walk leaves the component";
  } else if (clash[0] != kInvalid) {
    why = "grid point maps to two mesh vertices (mesh vertices " + std::to_string(clash[0]) + " and " +
          std::to_string(clash[1]) + ")";
  }
  // Every grid point a mesh vertex, whatever the caller checks next: canonicalize reads the positions
  // of these vertices, and a partition need not have had its tiling checked (partition_from_cuts).
  if (why.empty() && std::find(map.vertex.begin(), map.vertex.end(), kInvalid) != map.vertex.end())
    why = "a grid point has no mesh vertex";
  return why;
}

}  // namespace

std::string number_schematic(const Schematic& s, Numbering& n) {
  std::uint64_t next = s.vertex_count;
  n.edge_base.resize(s.edge_count());
  for (std::uint32_t e = 0; e < s.edge_count(); ++e) {
    n.edge_base[e] = static_cast<std::uint32_t>(next);
    next += s.edge_length[e] - 1;
  }
  // Sizes first (as patch_size gives them, in the same walk), so that the rings fill one array.
  n.patches.assign(s.face_count(), {});
  std::uint64_t ring_total = 0;
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    PatchGrid& g = n.patches[f];
    const std::uint32_t d0 = s.face_dart[f];
    std::uint32_t d = d0, side = 0;
    std::uint64_t ring = 0;
    do {
      const std::uint32_t len = s.edge_length[d >> 1];
      ring += len;
      if (side == 0) g.a += len;
      if (side == 1) g.b += len;
      d = s.dart_next[d];
      if (s.dart_corner[d]) ++side;
    } while (d != d0);
    if (ring != 2ull * (g.a + g.b)) return "patch " + std::to_string(f) + " has unequal opposite sides";
    g.interior_base = static_cast<std::uint32_t>(next);
    next += static_cast<std::uint64_t>(g.a - 1) * (g.b - 1);
    if (next > 0xFFFFFFF0u) return "too many vertices";
    ring_total += ring;
  }
  n.vertex_count = static_cast<std::uint32_t>(next);
  n.rings.resize(ring_total);
  std::uint32_t* r = n.rings.data();
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    PatchGrid& g = n.patches[f];
    g.ring = {r, 2ull * (g.a + g.b)};
    const std::uint32_t d0 = s.face_dart[f];
    std::uint32_t d = d0;
    do {
      const std::uint32_t e = d >> 1, len = s.edge_length[e], base = n.edge_base[e];
      *r++ = s.dart_vertex[d];
      if (d & 1) {
        for (std::uint32_t k = len; k > 1; --k) *r++ = base + k - 2;
      } else {
        for (std::uint32_t k = 1; k < len; ++k) *r++ = base + k - 1;
      }
      d = s.dart_next[d];
    } while (d != d0);
  }
  return {};
}

PatchWalks walk_patches(const ComponentPartition& part, const Adjacency& adj) noexcept {
  PatchWalks w;
  try {
    const Schematic& s = part.schematic;
    const std::uint32_t nf = s.face_count();
    w.a.assign(nf, 0);
    w.b.assign(nf, 0);
    w.cell_begin.assign(nf + 1, 0);
    w.point_begin.assign(nf + 1, 0);
    for (std::uint32_t f = 0; f < nf; ++f) {
      std::uint64_t cells = 0, points = 0;
      if (!s.face_hole[f]) {
        const PatchSize z = patch_size(s, f);
        if (z.a == 0 || z.b == 0) return w;
        w.a[f] = z.a, w.b[f] = z.b;
        cells = std::uint64_t{z.a} * z.b;
        points = (std::uint64_t{z.a} + 1) * (z.b + 1);
      }
      w.cell_begin[f + 1] = w.cell_begin[f] + cells;
      w.point_begin[f + 1] = w.point_begin[f] + points;
      if (w.cell_begin[f + 1] > adj.component_faces[part.component]) return w;
    }
    w.cell.resize(w.cell_begin[nf]);
    w.point.assign(w.point_begin[nf], kInvalid);
    for (std::uint32_t f = 0; f < nf; ++f) {
      if (s.face_hole[f]) continue;
      const std::uint32_t a = w.a[f], b = w.b[f];
      std::uint32_t* const cell = &w.cell[w.cell_begin[f]];
      std::uint32_t* const point = &w.point[w.point_begin[f]];
      std::uint32_t h = s.dart_halfedge[s.face_dart[f]];
      for (std::uint32_t j = 0; j < b; ++j) {
        std::uint32_t g = h;
        for (std::uint32_t i = 0; i < a; ++i) {
          const std::uint32_t face = adj.face(g);
          if (face == kInvalid || adj.face_component[face] != part.component) return w;
          cell[j * a + i] = g;
          const std::uint32_t* const corner = &adj.origin[g & ~3u];
          const std::size_t p = std::size_t{j} * (a + 1) + i;
          const std::size_t at[4] = {p, p + 1, p + a + 2, p + a + 1};
          for (std::uint32_t k = 0; k < 4; ++k) {
            const std::uint32_t mv = corner[(g + k) & 3u];
            if (point[at[k]] != mv && point[at[k]] != kInvalid) return w;
            point[at[k]] = mv;
          }
          if (i + 1 < a) g = right_of(adj, g);
        }
        if (j + 1 < b) h = up_of(adj, h);
      }
    }
    w.ok = true;
  } catch (...) {
    w.ok = false;  // link decides
  }
  return w;
}

bool link_from_walks(const ComponentPartition& relabelled, const Schematic& original,
                     std::span<const std::uint32_t> order, const PatchWalks& walks, LayoutMap& map) {
  const Schematic& s = relabelled.schematic;
  if (!walks.ok || order.size() != s.dart_count()) return false;
  Numbering n;
  if (!number_schematic(s, n).empty()) return false;
  map.vertex.assign(n.vertex_count, kInvalid);
  // As many cells as the walks hold, if the patches are theirs (checked patch by patch).
  map.face.resize(walks.cell.size());
  map.rotation.resize(walks.cell.size());
  std::uint32_t* face = map.face.data();
  std::uint8_t* rotation = map.rotation.data();
  std::uint64_t cells = 0;
  std::vector<std::uint32_t> row;
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    // The patch is the one of original's face under its first corner dart, turned so that its grid
    // starts at that face's corner k: k quarter turns, its cells' bottom half-edges k corners on.
    const std::uint32_t od = order[s.face_dart[f]], of = original.dart_face[od];
    if (!original.dart_corner[original.face_dart[of]]) return false;
    std::uint32_t k = 0;
    for (std::uint32_t d = original.face_dart[of]; d != od && k < 4;) {
      d = original.dart_next[d];
      k += original.dart_corner[d];
    }
    const PatchGrid& g = n.patches[f];
    const std::uint32_t a = walks.a[of], b = walks.b[of];
    if (k >= 4 || g.a != (k & 1 ? b : a) || g.b != (k & 1 ? a : b)) return false;
    cells += std::uint64_t{a} * b;
    if (cells > walks.cell.size()) return false;
    const std::uint32_t* const cell = &walks.cell[walks.cell_begin[of]];
    const std::uint32_t* const point = &walks.point[walks.point_begin[of]];
    // Cell (i, j) of the turned grid is the original's c0 + i * ci + j * cj (a cells a row), point (i, j)
    // the original's p0 + i * pi + j * pj (a + 1 points a row).
    const std::int64_t A = a, B = b, W = A + 1;
    std::int64_t st[6];
    if (k == 0) st[0] = 0, st[1] = 1, st[2] = A, st[3] = 0, st[4] = 1, st[5] = W;
    if (k == 1) st[0] = A - 1, st[1] = A, st[2] = -1, st[3] = A, st[4] = W, st[5] = -1;
    if (k == 2) st[0] = A * B - 1, st[1] = -1, st[2] = -A, st[3] = B * W + A, st[4] = -1, st[5] = -W;
    if (k == 3) st[0] = (B - 1) * A, st[1] = -A, st[2] = 1, st[3] = B * W, st[4] = -W, st[5] = 1;
    for (std::uint32_t j = 0; j < g.b; ++j) {
      std::int64_t c = st[0] + j * st[2];  // an index: a pointer would step outside the array
      for (std::uint32_t i = 0; i < g.a; ++i, c += st[1]) {
        const std::uint32_t turned = (cell[c] & ~3u) | ((cell[c] + k) & 3u);
        *face++ = turned >> 2;
        *rotation++ = static_cast<std::uint8_t>(turned & 3);
      }
    }
    row.resize(std::size_t{g.a} + 1);
    for (std::uint32_t j = 0; j <= g.b; ++j) {
      g.row(j, row.data());
      std::int64_t p = st[3] + j * st[5];
      for (std::uint32_t i = 0; i <= g.a; ++i, p += st[4]) {
        std::uint32_t& slot = map.vertex[row[i]];
        if (slot != point[p] && slot != kInvalid) return false;
        slot = point[p];
      }
    }
  }
  return cells == walks.cell.size() &&
         std::find(map.vertex.begin(), map.vertex.end(), kInvalid) == map.vertex.end();
}

GridLayout grid_layout(const ComponentPartition& part, Numbering& n) {
  GridLayout out;
  const bool general = part.kind == ComponentKind::kUnstructured || part.kind == ComponentKind::kDisk;
  if (general) {
    std::string why = number_schematic(part.schematic, n);
    if (!why.empty()) throw Error(ErrorCode::kFormat, "schematic: " + why);
  }
  out.vertex_count = layout_vertex_count(part, n);
  out.quads.resize(4 * std::size_t{layout_face_count(part, n)});
  std::uint32_t* q = out.quads.data();
  for_each_cell(part, &n, nullptr, [&q](const std::uint32_t* c, std::uint32_t) {
    std::copy(c, c + 4, q);
    q += 4;
    return true;
  });
  return out;
}

GridLayout grid_layout(const ComponentPartition& part) {
  Numbering n;
  return grid_layout(part, n);
}

LayoutMap layout_to_mesh(const ComponentPartition& part, const Adjacency& adj) {
  LayoutMap map;
  std::string why = link(part, adj, map);
  if (!why.empty()) throw Error(ErrorCode::kInternal, "layout: " + why);
  return map;
}

std::string validate(const ComponentPartition& part, const Adjacency* adj) {
  auto fail = [](const std::string& s) { return s; };
  if (part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus) {
    // An annulus of fewer than 3 faces around glues faces onto themselves or closes into a pillow. A
    // torus may be one helical row (b = 1, twisted): whether its sizes and twist glue into a manifold
    // is left to the check on the rebuilt mesh (decode).
    if (part.a < 1 || part.b < 1) return fail("structured component has an empty side");
    if (part.kind == ComponentKind::kAnnulus && part.a < 3)
      return fail("annulus of " + std::to_string(part.a) + " faces around (at least 3)");
    if (part.kind == ComponentKind::kTorus ? part.twist >= part.a : part.twist != 0) return fail("bad twist");
  } else {
    const Schematic& s = part.schematic;
    const std::uint32_t nd = s.dart_count();
    if (nd == 0 || nd % 2) return fail("schematic has no edges or an odd number of darts");
    if (s.edge_count() * 2 != nd || s.dart_next.size() != nd || s.dart_prev.size() != nd ||
        s.dart_face.size() != nd || s.dart_corner.size() != nd || s.face_hole.size() != s.face_count())
      return fail("schematic arrays disagree in size");
    for (std::uint32_t e = 0; e < s.edge_count(); ++e)
      if (s.edge_length[e] == 0) return fail("edge " + std::to_string(e) + " has length 0");
    std::vector<std::uint32_t> degree(s.vertex_count, 0), vertex_corners(s.vertex_count, 0);
    for (std::uint32_t d = 0; d < nd; ++d) {
      if (s.dart_next[d] >= nd || s.dart_prev[s.dart_next[d]] != d) return fail("next/prev disagree");
      if (s.dart_vertex[d] >= s.vertex_count || s.dart_face[d] >= s.face_count()) return fail("bad dart ids");
      if (s.dart_vertex[s.dart_next[d ^ 1]] != s.dart_vertex[d]) return fail("vertex rotation broken");
      if (s.dart_face[s.dart_next[d]] != s.dart_face[d]) return fail("face cycle broken");
      ++degree[s.dart_vertex[d]];
      vertex_corners[s.dart_vertex[d]] += s.dart_corner[d];
    }
    for (std::uint32_t v = 0; v < s.vertex_count; ++v) {
      if (degree[v] < 2) return fail("vertex " + std::to_string(v) + " has fewer than two edges");
      if (degree[v] == 2 && vertex_corners[v] == 0)
        return fail("vertex " + std::to_string(v) + " has two edges and no corner");
    }
    // Faces: cycles of next; each a disk (a cycle in a combinatorial map); 0 or 4 corners.
    std::vector<std::uint32_t> seen(s.face_count(), 0);
    for (std::uint32_t f = 0; f < s.face_count(); ++f) {
      const std::uint32_t d0 = s.face_dart[f];
      if (d0 >= nd || s.dart_face[d0] != f)
        return fail("face_dart of face " + std::to_string(f) + " is not in it");
      std::uint32_t corners = 0, len = 0, d = d0;
      do {
        corners += s.dart_corner[d];
        ++len;
        d = s.dart_next[d];
      } while (d != d0 && len <= nd);
      seen[f] = len;
      if (s.face_hole[f] ? corners != 0 : corners != 4)
        return fail("face " + std::to_string(f) + " has " + std::to_string(corners) + " corners");
      if (!s.face_hole[f]) {
        if (!s.dart_corner[d0]) return fail("patch " + std::to_string(f) + " does not start at a corner");
        // Four sides; opposite sides of equal length.
        std::uint64_t side[4] = {0, 0, 0, 0};
        int k = -1;
        d = d0;
        do {
          if (s.dart_corner[d]) ++k;
          side[k] += s.edge_length[d >> 1];
          d = s.dart_next[d];
        } while (d != d0);
        if (side[0] != side[2] || side[1] != side[3])
          return fail("patch " + std::to_string(f) + " has sides " + std::to_string(side[0]) + "," +
                      std::to_string(side[1]) + "," + std::to_string(side[2]) + "," +
                      std::to_string(side[3]));
      }
    }
    std::uint64_t total = 0;
    for (std::uint32_t f = 0; f < s.face_count(); ++f) total += seen[f];
    if (total != nd) return fail("darts belong to no listed face");
    for (std::uint32_t e = 0; e < s.edge_count(); ++e)
      if (s.face_hole[s.dart_face[2 * e]] && s.face_hole[s.dart_face[2 * e + 1]])
        return fail("edge " + std::to_string(e) + " lies between two holes");
  }
  if (!adj) return {};
  LayoutMap map;
  std::string why = link(part, *adj, map);
  if (!why.empty()) return why;
  std::vector<std::uint8_t> face_seen, vertex_seen;
  return check_tiling(part, *adj, map, face_seen, vertex_seen);
}

std::string check_tiling(const ComponentPartition& part, const Adjacency& adj, const LayoutMap& map,
                         std::vector<std::uint8_t>& face_seen, std::vector<std::uint8_t>& vertex_seen) {
  // Exact tiling: the layout maps one-to-one onto the component's vertices and faces. The scratch
  // arrays are shared between components and left all zero again, so a whole mesh costs O(n).
  face_seen.resize(adj.face_count, 0);
  vertex_seen.resize(adj.vertex_count, 0);
  std::string why;
  for (std::uint32_t f : map.face) {
    if (face_seen[f]) {
      why = "face " + std::to_string(f) + " lies in two patches";
      break;
    }
    face_seen[f] = 1;
  }
  if (why.empty() && map.face.size() != adj.component_faces[part.component])
    why = "patches do not cover the component";
  for (std::uint32_t v : map.vertex) {
    if (!why.empty()) break;
    if (v == kInvalid) {
      why = "a grid point has no mesh vertex";
    } else if (vertex_seen[v]) {
      why = "mesh vertex " + std::to_string(v) + " appears twice in the layout";
    } else {
      vertex_seen[v] = 1;
    }
  }
  for (std::uint32_t f : map.face) face_seen[f] = 0;
  for (std::uint32_t v : map.vertex)
    if (v != kInvalid) vertex_seen[v] = 0;
  return why;
}

}  // namespace qsp
