// From a schematic to the mesh it stands for (grid_layout), the link back to the input mesh
// (layout_to_mesh), and the checks of §4's definition (validate).
#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <queue>
#include <span>
#include <string>

#include "qsp/error.h"
#include "qsp/partition.h"

namespace qsp {
namespace {

std::uint32_t right_of(const Adjacency& adj, std::uint32_t h) { return adj.next(adj.twin[adj.next(h)]); }
std::uint32_t up_of(const Adjacency& adj, std::uint32_t h) { return adj.twin[adj.next(adj.next(h))]; }

// Grid points of one patch in layout numbering: P(i, j), 0 <= i <= a, 0 <= j <= b.
struct PatchGrid {
  std::uint32_t a = 0, b = 0;
  std::vector<std::uint32_t> ring;  // boundary points counter-clockwise from corner (0,0)
  std::uint32_t interior_base = 0;  // first id of the (a-1)(b-1) inner points, row by row
  std::uint32_t at(std::uint32_t i, std::uint32_t j) const {
    if (j == 0) return ring[i];
    if (i == a) return ring[a + j];
    if (j == b) return ring[2 * a + b - i];
    if (i == 0) return ring[2 * a + 2 * b - j];
    return interior_base + (j - 1) * (a - 1) + (i - 1);
  }
};

// Numbering of a general schematic's vertices: X, then edge-inner, then patch-inner points.
struct Numbering {
  std::vector<std::uint32_t> edge_base;  // per edge: id of its first inner point
  std::vector<PatchGrid> patches;        // per face (empty for holes)
  std::uint32_t vertex_count = 0;
};

// Returns an empty string, or why the schematic cannot be laid out.
std::string number_schematic(const Schematic& s, Numbering& n) {
  std::uint64_t next = s.vertex_count;
  n.edge_base.resize(s.edge_count());
  for (std::uint32_t e = 0; e < s.edge_count(); ++e) {
    n.edge_base[e] = static_cast<std::uint32_t>(next);
    next += s.edge_length[e] - 1;
  }
  n.patches.assign(s.face_count(), {});
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    PatchGrid& g = n.patches[f];
    const PatchSize size = patch_size(s, f);
    g.a = size.a;
    g.b = size.b;
    g.ring.reserve(2ull * (g.a + g.b));
    std::uint32_t d = s.face_dart[f];
    do {
      const std::uint32_t e = d >> 1, len = s.edge_length[e];
      g.ring.push_back(s.dart_vertex[d]);
      for (std::uint32_t k = 1; k < len; ++k)
        g.ring.push_back(n.edge_base[e] + ((d & 1) ? len - 1 - k : k - 1));
      d = s.dart_next[d];
    } while (d != s.face_dart[f]);
    if (g.ring.size() != 2ull * (g.a + g.b))
      return "patch " + std::to_string(f) + " has unequal opposite sides";
    g.interior_base = static_cast<std::uint32_t>(next);
    next += static_cast<std::uint64_t>(g.a - 1) * (g.b - 1);
    if (next > 0xFFFFFFF0u) return "too many vertices";
  }
  n.vertex_count = static_cast<std::uint32_t>(next);
  return {};
}

// Visits every cell of the layout with its layout corner ids and (when adj given) the mesh half-edge
// at its bottom; returns false from `visit` to stop.
template <class Visit>
void for_each_cell(const ComponentPartition& part, const Numbering* n, const Adjacency* adj, Visit&& visit) {
  std::uint32_t c[4];
  if (part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus) {
    const std::uint32_t a = part.a, b = part.b;
    auto P = [&](std::uint32_t x, std::uint32_t y) -> std::uint32_t {
      x %= a;
      if (part.kind == ComponentKind::kTorus && y == b) return (x + part.twist) % a;
      return y * a + x;
    };
    std::uint32_t row = adj ? part.anchor_halfedge : kInvalid;
    for (std::uint32_t y = 0; y < b; ++y) {
      std::uint32_t h = row;
      for (std::uint32_t x = 0; x < a; ++x) {
        c[0] = P(x, y), c[1] = P(x + 1, y), c[2] = P(x + 1, y + 1), c[3] = P(x, y + 1);
        if (!visit(c, h)) return;
        if (adj) h = right_of(*adj, h);
      }
      if (adj) row = up_of(*adj, row);
    }
    return;
  }
  const Schematic& s = part.schematic;
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    const PatchGrid& g = n->patches[f];
    std::uint32_t row = adj ? s.dart_halfedge[s.face_dart[f]] : kInvalid;
    for (std::uint32_t j = 0; j < g.b; ++j) {
      std::uint32_t h = row;
      for (std::uint32_t i = 0; i < g.a; ++i) {
        c[0] = g.at(i, j), c[1] = g.at(i + 1, j), c[2] = g.at(i + 1, j + 1), c[3] = g.at(i, j + 1);
        if (!visit(c, h)) return;
        if (adj && i + 1 < g.a) h = right_of(*adj, h);
      }
      if (adj && j + 1 < g.b) row = up_of(*adj, row);
    }
  }
}

std::uint32_t layout_vertex_count(const ComponentPartition& part, const Numbering& n) {
  if (part.kind == ComponentKind::kAnnulus) return part.a * (part.b + 1);
  if (part.kind == ComponentKind::kTorus) return part.a * part.b;
  return n.vertex_count;
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
  std::string why;
  for_each_cell(part, &n, &adj, [&](const std::uint32_t* c, std::uint32_t h) {
    const std::uint32_t f = adj.face(h);
    if (f == kInvalid || adj.face_component[f] != part.component) {
      why = "grid walk leaves the component";
      return false;
    }
    map.face.push_back(f);
    map.rotation.push_back(static_cast<std::uint8_t>(h & 3));
    for (std::uint32_t k = 0; k < 4; ++k) {
      const std::uint32_t mv = adj.origin[(h & ~3u) | ((h + k) & 3u)];
      std::uint32_t& slot = map.vertex[c[k]];
      if (slot == kInvalid) {
        slot = mv;
      } else if (slot != mv) {
        why = "grid point maps to two mesh vertices (mesh vertices " + std::to_string(slot) + " and " +
              std::to_string(mv) + ")";
        return false;
      }
    }
    return true;
  });
  return why;
}

// Boundary point r of a patch ring as grid coordinates, and the side it is on (0 bottom, 1 right,
// 2 top, 3 left; a corner counts as the side that starts at it).
struct RingPoint {
  std::int64_t i, j;
  int side;
};
RingPoint ring_point(const PatchGrid& g, std::int64_t r) {
  const std::int64_t a = g.a, b = g.b;
  if (r < a) return {r, 0, 0};
  if (r < a + b) return {a, r - a, 1};
  if (r < 2 * a + b) return {2 * a + b - r, b, 2};
  return {0, 2 * a + 2 * b - r, 3};
}

// The stencil fields o/ow/ofar (edge points) and x0/x1/x2/xnum/xden (schematic vertices): the
// opposite side of a patch, or its corners, predict a point far better than its own edge can when
// patches are small (coarse meshes with many extraordinary vertices).
void across_patches(const Schematic& s, const Numbering& n, std::vector<GridLayout::Stencil>& st) {
  const std::uint32_t edge_end =
      s.vertex_count +
      static_cast<std::uint32_t>(
          std::accumulate(s.edge_length.begin(), s.edge_length.end(), std::uint64_t{0}) - s.edge_count());
  std::vector<std::uint32_t> across(edge_end, kInvalid);  // patch distance to o, for the nearest patch
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    const PatchGrid& g = n.patches[f];
    const auto ring = static_cast<std::int64_t>(g.ring.size());
    const std::int64_t a = g.a, b = g.b;
    static constexpr std::int64_t kStep[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    for (std::int64_t r = 0; r < ring; ++r) {
      const std::uint32_t x = g.ring[r];
      const RingPoint p = ring_point(g, r);
      auto at = [&](std::int64_t i, std::int64_t j) {
        return g.at(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
      };
      GridLayout::Stencil& t = st[x];
      if (x < s.vertex_count) {
        const bool corner = (p.i == 0 || p.i == a) && (p.j == 0 || p.j == b);
        if (corner) {
          if (t.x2 != kInvalid) continue;
          const std::uint32_t c1 = at(a - p.i, p.j), c2 = at(p.i, b - p.j), c0 = at(a - p.i, b - p.j);
          if (c0 < x && c1 < x && c2 < x) t.x0 = c0, t.x1 = c1, t.x2 = c2, t.xnum = t.xden = 0;
        } else if (t.x0 == kInvalid) {
          // On a side: the lerp between that side's corners.
          const bool horizontal = p.side == 0 || p.side == 2;
          const std::uint32_t c0 = horizontal ? at(0, p.j) : at(p.i, 0),
                              c1 = horizontal ? at(a, p.j) : at(p.i, b);
          if (c0 < x && c1 < x) {
            t.x0 = c0, t.x1 = c1;
            t.xnum = static_cast<std::uint32_t>(horizontal ? p.i : p.j);
            t.xden = static_cast<std::uint32_t>(horizontal ? a : b);
          }
        }
        continue;
      }
      if (x >= edge_end) continue;
      // Edge point: w is one ring step away, far the other way; map all three across the patch.
      const std::int64_t dir = g.ring[(r + ring - 1) % ring] == t.w ? -1 : 1;
      const std::int64_t di = kStep[p.side][0], dj = kStep[p.side][1];
      auto opposite = [&](std::int64_t i, std::int64_t j) {
        return p.side == 0 || p.side == 2 ? at(i, b - j) : at(a - i, j);
      };
      const std::int64_t fd = t.far_dist, wi = p.i + dir * di, wj = p.j + dir * dj;
      const std::int64_t fi = p.i - dir * fd * di, fj = p.j - dir * fd * dj;
      if (wi < 0 || wi > a || wj < 0 || wj > b || fi < 0 || fi > a || fj < 0 || fj > b) continue;
      const std::uint32_t o = opposite(p.i, p.j), ow = opposite(wi, wj), of = opposite(fi, fj);
      if (o >= x || ow >= x) continue;
      const std::uint32_t dist =
          static_cast<std::uint32_t>(p.side == 0 || p.side == 2 ? b : a) * 2 + (of < x ? 0 : 1);
      if (dist >= across[x]) continue;
      across[x] = dist;
      t.o = o, t.ow = ow, t.ofar = of < x ? of : kInvalid;
    }
  }
}

// Patch coding order (CodingOrder::kPatch, geometry revision 3). Patches are visited greedily, the one
// with the largest share of its boundary already coded next; each is turned so that its raster starts
// at the corner whose two sides are most coded, and its points are coded row by row where the raster
// first reaches them. A point's stencil is that patch's grid frame, extended one step across the
// bottom and left sides into the patches there; without a frame parallelogram it takes a finished
// cell around it, else its row or column. Every point, schematic vertices included, is then predicted
// from mesh neighbours one edge away, where layout order predicts schematic vertices from others a
// patch side away: 5-22% smaller at 14 bits on coarse meshes with small patches (horse, gargoyle).
void patch_order(const Schematic& s, const Numbering& n, GridLayout& out) {
  const std::uint32_t count = out.vertex_count, vc = s.vertex_count;
  const std::uint32_t edge_end =
      vc +
      static_cast<std::uint32_t>(
          std::accumulate(s.edge_length.begin(), s.edge_length.end(), std::uint64_t{0}) - s.edge_count());
  // Each edge point's seats: (patch, ring index) in the up to two patches beside its edge.
  struct Seat {
    std::uint32_t f = kInvalid, r = 0;
  };
  std::vector<std::array<Seat, 2>> seats(edge_end - vc);
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    const PatchGrid& g = n.patches[f];
    for (std::uint32_t r = 0; r < g.ring.size(); ++r) {
      const std::uint32_t x = g.ring[r];
      if (x < vc || x >= edge_end) continue;
      auto& seat = seats[x - vc];
      (seat[0].f == kInvalid ? seat[0] : seat[1]) = Seat{f, r};
    }
  }
  // The neighbour of edge point x one step into the patch beside it other than f (kInvalid if none).
  auto across = [&](std::uint32_t x, std::uint32_t f) {
    if (x < vc || x >= edge_end) return kInvalid;
    for (const Seat& seat : seats[x - vc]) {
      if (seat.f == kInvalid || seat.f == f) continue;
      const PatchGrid& q = n.patches[seat.f];
      RingPoint p = ring_point(q, seat.r);
      if (p.side == 0) p.j = 1;
      if (p.side == 1) p.i = q.a - 1;
      if (p.side == 2) p.j = q.b - 1;
      if (p.side == 3) p.i = 1;
      return q.at(static_cast<std::uint32_t>(p.i), static_cast<std::uint32_t>(p.j));
    }
    return kInvalid;
  };
  // Cells around each layout vertex (CSR over quad corners), for points without a frame.
  std::vector<std::uint32_t> first(count + 1, 0), at_cell(out.quads.size());
  for (std::uint32_t v : out.quads) ++first[v + 1];
  for (std::uint32_t v = 0; v < count; ++v) first[v + 1] += first[v];
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t k = 0; k < out.quads.size(); ++k) at_cell[fill[out.quads[k]]++] = k;
  }
  std::vector<std::uint32_t> id(count, kInvalid);  // layout vertex -> coding position
  std::vector<GridLayout::Stencil> st;             // in coding positions
  st.reserve(count);
  out.coding.clear();
  out.coding.reserve(count);
  auto coded = [&](std::uint32_t q) { return q != kInvalid && id[q] != kInvalid ? q : kInvalid; };
  // Patches holding each boundary point (CSR over ring entries), for choosing the next patch.
  std::vector<std::uint32_t> ring_first(edge_end + 1, 0), ring_patch;
  for (std::uint32_t f = 0; f < s.face_count(); ++f)
    if (!s.face_hole[f])
      for (std::uint32_t x : n.patches[f].ring) ++ring_first[x + 1];
  for (std::uint32_t x = 0; x < edge_end; ++x) ring_first[x + 1] += ring_first[x];
  ring_patch.resize(ring_first[edge_end]);
  {
    std::vector<std::uint32_t> fill(ring_first.begin(), ring_first.end() - 1);
    for (std::uint32_t f = 0; f < s.face_count(); ++f)
      if (!s.face_hole[f])
        for (std::uint32_t x : n.patches[f].ring) ring_patch[fill[x]++] = f;
  }
  // Next patch: the one with the largest share of its boundary ring coded (ties: lowest index), so
  // rows start from coded sides. Shares compare exactly (cross products); stale heap entries (a count
  // since raised) are skipped.
  std::vector<std::uint32_t> ring_coded(s.face_count(), 0);
  std::vector<std::uint8_t> visited(s.face_count(), 0);
  struct Candidate {
    std::uint64_t coded, ring;
    std::uint32_t f;
    bool operator<(const Candidate& o) const {  // "less urgent than"
      const std::uint64_t l = coded * o.ring, r = o.coded * ring;
      return l != r ? l < r : f > o.f;
    }
  };
  std::priority_queue<Candidate> next;
  std::uint32_t scan = 0;  // lowest patch not yet visited, when no patch touches the coded part
  std::vector<std::uint32_t> turned;
  for (;;) {
    std::uint32_t f = kInvalid;
    while (!next.empty()) {
      const Candidate c = next.top();
      next.pop();
      if (!visited[c.f] && c.coded == ring_coded[c.f]) {
        f = c.f;
        break;
      }
    }
    if (f == kInvalid) {
      while (scan < s.face_count() && (s.face_hole[scan] || visited[scan])) ++scan;
      if (scan == s.face_count()) break;
      f = scan;
    }
    visited[f] = 1;
    const PatchGrid& g = n.patches[f];
    // The patch turned so that its raster starts at corner `rot` (0 = face_dart's): point (i, j) of
    // the turned (a, b)-grid.
    int rot = 0;
    std::int64_t a = g.a, b = g.b;
    auto at = [&](std::int64_t i, std::int64_t j) {
      std::int64_t x = i, y = j;
      if (rot == 1) x = g.a - j, y = i;
      if (rot == 2) x = g.a - i, y = g.b - j;
      if (rot == 3) x = j, y = g.b - i;
      return g.at(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    };
    // Grid point (i, j) of the turned patch, or one step beyond its left or bottom side: looked up in
    // `turned`, the turned grid's points row by row with that extra row and column (filled below).
    auto nb = [&](std::int64_t i, std::int64_t j) {
      return i >= -1 && i <= a && j >= -1 && j <= b
                 ? turned[static_cast<std::size_t>((j + 1) * (a + 2) + i + 1)]
                 : kInvalid;
    };
    // Start where most of the bottom and left sides are coded already (their rows then have a frame).
    std::int64_t best = -1;
    int rot_best = 0;
    for (int r = 0; r < 4; ++r) {
      rot = r;
      a = (r & 1) ? g.b : g.a, b = (r & 1) ? g.a : g.b;
      std::int64_t score = 0;
      for (std::int64_t i = 0; i <= a; ++i) score += id[at(i, 0)] != kInvalid;
      for (std::int64_t j = 1; j <= b; ++j) score += id[at(0, j)] != kInvalid;
      if (score > best) best = score, rot_best = r;
    }
    rot = rot_best;
    a = (rot & 1) ? g.b : g.a, b = (rot & 1) ? g.a : g.b;
    turned.assign(static_cast<std::size_t>((a + 2) * (b + 2)), kInvalid);
    for (std::int64_t j = 0; j <= b; ++j)
      for (std::int64_t i = 0; i <= a; ++i)
        turned[static_cast<std::size_t>((j + 1) * (a + 2) + i + 1)] = at(i, j);
    for (std::int64_t j = 0; j <= b; ++j)
      turned[static_cast<std::size_t>((j + 1) * (a + 2))] = across(at(0, j), f);
    for (std::int64_t i = 0; i <= a; ++i) turned[static_cast<std::size_t>(i + 1)] = across(at(i, 0), f);
    for (std::int64_t j = 0; j <= b; ++j)
      for (std::int64_t i = 0; i <= a; ++i) {
        const std::uint32_t p = nb(i, j);
        if (id[p] != kInvalid) continue;
        GridLayout::Stencil t;
        const std::uint32_t w = coded(nb(i - 1, j)), s0 = coded(nb(i, j - 1));
        const std::uint32_t sw = w != kInvalid && s0 != kInvalid ? coded(nb(i - 1, j - 1)) : kInvalid;
        if (sw != kInvalid) {  // the frame: everything a patch-inner point of layout order has, and more
          t.w = w, t.s = s0, t.sw = sw;
          t.ww = coded(nb(i - 2, j));
          t.se = coded(nb(i + 1, j - 1));
          t.ss = coded(nb(i, j - 2));
          t.sww = t.ww != kInvalid ? coded(nb(i - 2, j - 1)) : kInvalid;
          t.ssw = t.ss != kInvalid ? coded(nb(i - 1, j - 2)) : kInvalid;
          if (i < a && coded(nb(a, j)) != kInvalid && coded(nb(a, j - 1)) != kInvalid)
            t.e = nb(a, j), t.es = nb(a, j - 1), t.e_dist = static_cast<std::uint32_t>(a - i);
          if (j < b && coded(nb(i, b)) != kInvalid && coded(nb(i - 1, b)) != kInvalid)
            t.n = nb(i, b), t.nw = nb(i - 1, b), t.n_dist = static_cast<std::uint32_t>(b - j);
        } else {
          // A finished cell around p (the first in layout face order), as w, s, sw.
          const std::span<const std::uint32_t> around(at_cell.data() + first[p], first[p + 1] - first[p]);
          for (std::size_t k = 0; k < around.size() && t.w == kInvalid; ++k) {
            const std::uint32_t q = around[k] & ~3u, r = around[k] & 3u;
            const std::uint32_t u1 = out.quads[q + ((r + 1) & 3)], u2 = out.quads[q + ((r + 2) & 3)],
                                u3 = out.quads[q + ((r + 3) & 3)];
            if (coded(u1) != kInvalid && coded(u2) != kInvalid && coded(u3) != kInvalid)
              t.w = u3, t.s = u1, t.sw = u2;
          }
          if (t.w != kInvalid) {
            // done
          } else if (w != kInvalid) {  // along the row, towards its end if that is coded
            t.w = w;
            t.ww = coded(nb(i - 2, j));
            if (i < a && coded(nb(a, j)) != kInvalid)
              t.far = nb(a, j), t.far_dist = static_cast<std::uint32_t>(a - i);
          } else if (s0 != kInvalid) {  // along the column
            t.w = s0;
            t.ww = coded(nb(i, j - 2));
            if (j < b && coded(nb(i, b)) != kInvalid)
              t.far = nb(i, b), t.far_dist = static_cast<std::uint32_t>(b - j);
          } else {  // any coded neighbour (else the previous vertex stands in)
            for (std::size_t k = 0; k < around.size() && t.w == kInvalid; ++k) {
              const std::uint32_t q = around[k] & ~3u, r = around[k] & 3u;
              t.w = coded(out.quads[q + ((r + 1) & 3)]);
              if (t.w == kInvalid) t.w = coded(out.quads[q + ((r + 3) & 3)]);
            }
          }
        }
        // Every field names a coded vertex: into coding positions now, while t is in cache.
        for (std::uint32_t* v : t.vertex_fields())
          if (*v != kInvalid) *v = id[*v];
        id[p] = static_cast<std::uint32_t>(out.coding.size());
        out.coding.push_back(p);
        st.push_back(t);
        if (p < edge_end)
          for (std::uint32_t k = ring_first[p]; k < ring_first[p + 1]; ++k) {
            const std::uint32_t q = ring_patch[k];
            ++ring_coded[q];
            if (!visited[q]) next.push({ring_coded[q], n.patches[q].ring.size(), q});
          }
      }
  }
  if (out.coding.size() != count) throw Error(ErrorCode::kInternal, "patch order misses a vertex");
  out.stencil = std::move(st);
}

}  // namespace

GridLayout grid_layout(const ComponentPartition& part, CodingOrder order) {
  GridLayout out;
  Numbering n;
  const bool general = part.kind == ComponentKind::kUnstructured || part.kind == ComponentKind::kDisk;
  if (general) {
    std::string why = number_schematic(part.schematic, n);
    if (!why.empty()) throw Error(ErrorCode::kFormat, "schematic: " + why);
  }
  out.vertex_count = layout_vertex_count(part, n);
  for_each_cell(part, &n, nullptr, [&](const std::uint32_t* c, std::uint32_t) {
    out.quads.insert(out.quads.end(), c, c + 4);
    return true;
  });
  if (general && order == CodingOrder::kPatch) {  // its own stencils: none of layout order's are needed
    patch_order(part.schematic, n, out);
    return out;
  }
  out.stencil.assign(out.vertex_count, {});
  auto& st = out.stencil;
  if (!general) {
    const std::uint32_t a = part.a, rows = out.vertex_count / std::max(a, 1u);
    for (std::uint32_t y = 0; y < rows; ++y)
      for (std::uint32_t x = 0; x < a; ++x) {
        auto& t = st[y * a + x];
        if (x >= 1) t.w = y * a + x - 1;
        if (x >= 2) t.ww = y * a + x - 2;
        if (y >= 1) t.s = (y - 1) * a + x;
        if (x >= 1 && y >= 1) t.sw = (y - 1) * a + x - 1;
        if (order == CodingOrder::kPatch && x >= 1 && y >= 1) {
          // Patch order's stencils carry these explicitly; here they are what layout order derives.
          if (x + 1 < a) t.se = (y - 1) * a + x + 1;
          if (y >= 2) t.ss = (y - 2) * a + x, t.ssw = (y - 2) * a + x - 1;
          if (x >= 2) t.sww = (y - 1) * a + x - 2;
        }
      }
    return out;
  }
  const Schematic& s = part.schematic;
  // X vertices: predicted from a schematic neighbour numbered earlier, else the previous one.
  for (std::uint32_t d = 0; d < s.dart_count(); ++d) {
    const std::uint32_t v = s.dart_vertex[d], u = s.dart_vertex[d ^ 1];
    if (u < v && (st[v].w == kInvalid || u > st[v].w)) st[v].w = u;
  }
  for (std::uint32_t v = 1; v < s.vertex_count; ++v)
    if (st[v].w == kInvalid) st[v].w = v - 1;
  // Edge-inner points: along the edge from dart 2e's origin.
  for (std::uint32_t e = 0; e < s.edge_count(); ++e) {
    const std::uint32_t len = s.edge_length[e], base = n.edge_base[e], u = s.dart_vertex[2 * e];
    for (std::uint32_t k = 1; k < len; ++k) {
      auto& t = st[base + k - 1];
      t.w = k == 1 ? u : base + k - 2;
      t.ww = k == 1 ? kInvalid : (k == 2 ? u : base + k - 3);
      t.far = s.dart_vertex[2 * e + 1];
      t.far_dist = len - k;
    }
  }
  // Patch-inner points: all boundary points are numbered before them.
  for (std::uint32_t f = 0; f < s.face_count(); ++f) {
    if (s.face_hole[f]) continue;
    const PatchGrid& g = n.patches[f];
    for (std::uint32_t j = 1; j < g.b; ++j)
      for (std::uint32_t i = 1; i < g.a; ++i) {
        auto& t = st[g.at(i, j)];
        t.w = g.at(i - 1, j);
        t.ww = i >= 2 ? g.at(i - 2, j) : kInvalid;
        t.s = g.at(i, j - 1);
        t.sw = g.at(i - 1, j - 1);
        t.e = g.at(g.a, j), t.es = g.at(g.a, j - 1), t.e_dist = g.a - i;
        t.n = g.at(i, g.b), t.nw = g.at(i - 1, g.b), t.n_dist = g.b - j;
      }
  }
  across_patches(s, n, st);
  return out;
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
