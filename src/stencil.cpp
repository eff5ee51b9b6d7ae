// The geometry coder's coding orders and stencils (format-spec/geometry_section.md, "Coding orders
// and stencils"): layout order with its across-patch fields, and patch order.
#include "stencil.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <future>
#include <numeric>
#include <queue>
#include <span>
#include <string>

#include "beside.h"
#include "layout_grid.h"
#include "qsp/error.h"

namespace qsp {
namespace {

// A stencil as its words, and a mask of all ones on the words that name a vertex (from
// vertex_fields(), the one list of them): loops over fixed words that check or remap every vertex
// field without a branch per field.
constexpr std::size_t kWords = sizeof(Stencil) / sizeof(std::uint32_t);
static_assert(sizeof(Stencil) == kWords * sizeof(std::uint32_t));
using Words = std::array<std::uint32_t, kWords>;

const Words& vertex_word_mask() {
  static const Words mask = [] {
    constexpr std::uint32_t kMark = 0x9E3779B9u;  // no other field's default
    Stencil m;
    for (std::uint32_t* f : m.vertex_fields()) *f = kMark;
    Words words = std::bit_cast<Words>(m);
    for (std::uint32_t& w : words) w = w == kMark ? ~0u : 0u;
    return words;
  }();
  return mask;
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
void across_patches(const Schematic& s, const Numbering& n, std::vector<Stencil>& st) {
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
      Stencil& t = st[x];
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

// A patch's points row by row (PatchGrid::row, not PatchGrid::at's tests of which side a point is on
// at every read: they were a seventh of patch order), turned so that its raster starts at corner `rot`
// (0 = face_dart's): point (i, j) of the turned (a, b)-grid is grid[origin + i * di + j * dj].
class Raster {
 public:
  void load(const PatchGrid& g) {
    g_ = &g;
    width_ = std::int64_t{g.a} + 1;
    grid_.resize(static_cast<std::size_t>(width_ * (std::int64_t{g.b} + 1)));
    for (std::uint32_t j = 0; j <= g.b; ++j) g.row(j, &grid_[static_cast<std::size_t>(j * width_)]);
    turn(0);
  }
  void turn(int r) {
    rot = r;
    const std::int64_t top = std::int64_t{g_->b} * width_;
    origin_ = r == 0 ? 0 : r == 1 ? g_->a : r == 2 ? top + g_->a : top;
    di_ = r == 0 ? 1 : r == 1 ? width_ : r == 2 ? -1 : -width_;
    dj_ = r == 0 ? width_ : r == 1 ? -1 : r == 2 ? -width_ : 1;
    a = (r & 1) ? g_->b : g_->a, b = (r & 1) ? g_->a : g_->b;
  }
  std::uint32_t at(std::int64_t i, std::int64_t j) const {
    return grid_[static_cast<std::size_t>(origin_ + i * di_ + j * dj_)];
  }
  int rot = 0;
  std::int64_t a = 0, b = 0;  // the turned grid's size

 private:
  const PatchGrid* g_ = nullptr;
  std::vector<std::uint32_t> grid_;
  std::int64_t width_ = 0, origin_ = 0, di_ = 1, dj_ = 0;
};

// A patch as patch order visits it: turned by `rot`, coding positions [begin, end) for its points not
// coded before.
struct Visit {
  std::uint32_t f;
  int rot;
  std::uint32_t begin, end;
};

// From this many points, patch order builds its stencils on two threads: the order is found first,
// then every stencil depends only on it.
constexpr std::uint32_t kStencilsBesideFrom = 4096;

// Patch coding order (CodingOrder::kPatch). Patches are visited greedily, the one
// with the largest share of its boundary already coded next; each is turned so that its raster starts
// at the corner whose two sides are most coded, and its points are coded row by row where the raster
// first reaches them. A point's stencil is that patch's grid frame, extended one step across the
// bottom and left sides into the patches there; without a frame parallelogram it takes a finished
// cell around it, else its row or column. Every point, schematic vertices included, is then predicted
// from mesh neighbours one edge away, where layout order predicts schematic vertices from others a
// patch side away: 5-22% smaller at 14 bits on coarse meshes with small patches (horse, gargoyle).
// Appends to `stencil` and `coding`, which hold the `base` positions of the components before this one
// (assemble() passes the mesh's arrays: no per-component copy to shift). The order is found first (a
// point is coded before p exactly when its position is smaller), then the stencils, in two halves on
// two threads for large components.
void patch_order(const Schematic& s, const Numbering& n, const GridLayout& layout, std::uint32_t base,
                 std::vector<Stencil>& stencil, std::vector<std::uint32_t>& coding) {
  const std::uint32_t count = layout.vertex_count, vc = s.vertex_count;
  const std::uint32_t edge_end =
      vc +
      static_cast<std::uint32_t>(
          std::accumulate(s.edge_length.begin(), s.edge_length.end(), std::uint64_t{0}) - s.edge_count());
  if (coding.size() != base || stencil.size() != base)
    throw Error(ErrorCode::kInternal, "patch order appended at the wrong position");
  // Each edge point's seats: (patch, ring index) in the up to two patches beside its edge; and the cells
  // around each layout vertex (CSR over quad corners), for points without a frame. Only the stencils
  // read them: built beside the order.
  struct Seat {
    std::uint32_t f = kInvalid, r = 0;
  };
  std::vector<std::array<Seat, 2>> seats;
  std::vector<std::uint32_t> first, at_cell;
  auto build_lookups = [&] {
    seats.assign(edge_end - vc, {});
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
    first.assign(count + 1, 0);
    at_cell.resize(layout.quads.size());
    for (std::uint32_t v : layout.quads) ++first[v + 1];
    for (std::uint32_t v = 0; v < count; ++v) first[v + 1] += first[v];
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t k = 0; k < layout.quads.size(); ++k) at_cell[fill[layout.quads[k]]++] = k;
  };
  const bool two = count >= kStencilsBesideFrom;
  auto lookups = beside(two, build_lookups);

  // The order. id: layout vertex -> coding position; cell: per position, the point's place (i, j) in its
  // patch's turned raster, as (j + 2) * (a + 4) + i + 2.
  std::vector<std::uint32_t> id(count, kInvalid), cell_of(count);
  std::vector<Visit> visits;
  coding.reserve(std::size_t{base} + count);
  std::uint32_t position = 0;  // this component's next coding position
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
  std::vector<std::uint32_t> touched, touched_by(s.face_count(), kInvalid);  // this patch's neighbours
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
  Raster raster;
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
    raster.load(n.patches[f]);
    // Start where most of the bottom and left sides are coded already (their rows then have a frame).
    std::int64_t best = -1;
    int rot_best = 0;
    for (int r = 0; r < 4; ++r) {
      raster.turn(r);
      std::int64_t score = 0;
      for (std::int64_t i = 0; i <= raster.a; ++i) score += id[raster.at(i, 0)] != kInvalid;
      for (std::int64_t j = 1; j <= raster.b; ++j) score += id[raster.at(0, j)] != kInvalid;
      if (score > best) best = score, rot_best = r;
    }
    raster.turn(rot_best);
    const std::uint32_t begin = position;
    for (std::int64_t j = 0; j <= raster.b; ++j)
      for (std::int64_t i = 0; i <= raster.a; ++i) {
        const std::uint32_t p = raster.at(i, j);
        if (id[p] != kInvalid) continue;
        cell_of[position] = static_cast<std::uint32_t>((j + 2) * (raster.a + 4) + i + 2);
        id[p] = position++;
        coding.push_back(p + base);
        if (p < edge_end)
          for (std::uint32_t k = ring_first[p]; k < ring_first[p + 1]; ++k) {
            const std::uint32_t q = ring_patch[k];
            ++ring_coded[q];
            if (!visited[q] && touched_by[q] != f) touched_by[q] = f, touched.push_back(q);
          }
      }
    if (position != begin) visits.push_back({f, rot_best, begin, position});
    // The patches this one's points reached, once each with their count now: the heap holds an entry
    // with each unvisited patch's current count at every choice, as when one went in per point, with
    // a fraction of the entries (the heap was a quarter of this function).
    for (const std::uint32_t q : touched)
      if (!visited[q]) next.push({ring_coded[q], n.patches[q].ring.size(), q});
    touched.clear();
  }
  if (position != count) throw Error(ErrorCode::kInternal, "patch order misses a vertex");
  lookups.get();

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
  // The stencils of the points of visits [from, to), into their positions.
  stencil.resize(std::size_t{base} + count);
  auto stencils = [&](std::size_t from, std::size_t to) {
    Raster turn;
    std::vector<std::uint32_t> turned;
    for (std::size_t v = from; v < to; ++v) {
      const Visit& visit = visits[v];
      const std::uint32_t f = visit.f;
      turn.load(n.patches[f]);
      turn.turn(visit.rot);
      const std::int64_t a = turn.a, b = turn.b;
      // Grid point (i, j) of the turned patch, or one step beyond its left or bottom side: looked up in
      // `turned`, the turned grid's points row by row with that extra row and column, in a border of
      // kInvalid wide enough for every (i, j) read, -2 <= i <= a + 1 and -2 <= j <= b (no bounds tests).
      auto cell = [&](std::int64_t i, std::int64_t j) {
        return static_cast<std::size_t>((j + 2) * (a + 4) + i + 2);
      };
      auto nb = [&](std::int64_t i, std::int64_t j) { return turned[cell(i, j)]; };
      turned.assign(static_cast<std::size_t>((a + 4) * (b + 3)), kInvalid);
      for (std::int64_t j = 0; j <= b; ++j)
        for (std::int64_t i = 0; i <= a; ++i) turned[cell(i, j)] = turn.at(i, j);
      for (std::int64_t j = 0; j <= b; ++j) turned[cell(-1, j)] = across(turn.at(0, j), f);
      for (std::int64_t i = 0; i <= a; ++i) turned[cell(i, -1)] = across(turn.at(i, 0), f);
      for (std::uint32_t k = visit.begin; k < visit.end; ++k) {
        const std::int64_t i = std::int64_t{cell_of[k] % (a + 4)} - 2,
                           j = std::int64_t{cell_of[k] / (a + 4)} - 2;
        const std::uint32_t p = coding[base + k] - base;
        // Coded before p: a smaller position (kInvalid, beyond the patches, is never coded).
        auto coded = [&](std::uint32_t q) { return q != kInvalid && id[q] < k ? q : kInvalid; };
        auto to_pos = [&](std::uint32_t q) { return id[q] + base; };  // q coded
        auto coded_pos = [&](std::uint32_t q) {
          return q != kInvalid && id[q] < k ? id[q] + base : kInvalid;
        };
        Stencil t;
        const std::uint32_t w = coded(nb(i - 1, j)), s0 = coded(nb(i, j - 1));
        const std::uint32_t sw = w != kInvalid && s0 != kInvalid ? coded(nb(i - 1, j - 1)) : kInvalid;
        if (sw != kInvalid) {  // the frame: everything a patch-inner point of layout order has, and more
          t.w = to_pos(w), t.s = to_pos(s0), t.sw = to_pos(sw);
          t.ww = coded_pos(nb(i - 2, j));
          t.se = coded_pos(nb(i + 1, j - 1));
          t.ss = coded_pos(nb(i, j - 2));
          t.sww = t.ww != kInvalid ? coded_pos(nb(i - 2, j - 1)) : kInvalid;
          t.ssw = t.ss != kInvalid ? coded_pos(nb(i - 1, j - 2)) : kInvalid;
          if (i < a && coded(nb(a, j)) != kInvalid && coded(nb(a, j - 1)) != kInvalid)
            t.e = to_pos(nb(a, j)), t.es = to_pos(nb(a, j - 1)), t.e_dist = static_cast<std::uint32_t>(a - i);
          if (j < b && coded(nb(i, b)) != kInvalid && coded(nb(i - 1, b)) != kInvalid)
            t.n = to_pos(nb(i, b)), t.nw = to_pos(nb(i - 1, b)), t.n_dist = static_cast<std::uint32_t>(b - j);
        } else {
          // A finished cell around p (the first in layout face order), as w, s, sw.
          const std::span<const std::uint32_t> around(at_cell.data() + first[p], first[p + 1] - first[p]);
          for (std::size_t c = 0; c < around.size() && t.w == kInvalid; ++c) {
            const std::uint32_t q = around[c] & ~3u, r = around[c] & 3u;
            const std::uint32_t u1 = layout.quads[q + ((r + 1) & 3)], u2 = layout.quads[q + ((r + 2) & 3)],
                                u3 = layout.quads[q + ((r + 3) & 3)];
            if (coded(u1) != kInvalid && coded(u2) != kInvalid && coded(u3) != kInvalid)
              t.w = to_pos(u3), t.s = to_pos(u1), t.sw = to_pos(u2);
          }
          if (t.w != kInvalid) {
            // done
          } else if (w != kInvalid) {  // along the row, towards its end if that is coded
            t.w = to_pos(w);
            t.ww = coded_pos(nb(i - 2, j));
            if (i < a && coded(nb(a, j)) != kInvalid)
              t.far = to_pos(nb(a, j)), t.far_dist = static_cast<std::uint32_t>(a - i);
          } else if (s0 != kInvalid) {  // along the column
            t.w = to_pos(s0);
            t.ww = coded_pos(nb(i, j - 2));
            if (j < b && coded(nb(i, b)) != kInvalid)
              t.far = to_pos(nb(i, b)), t.far_dist = static_cast<std::uint32_t>(b - j);
          } else {  // any coded neighbour (else the previous vertex stands in)
            for (std::size_t c = 0; c < around.size() && t.w == kInvalid; ++c) {
              const std::uint32_t q = around[c] & ~3u, r = around[c] & 3u;
              t.w = coded_pos(layout.quads[q + ((r + 1) & 3)]);
              if (t.w == kInvalid) t.w = coded_pos(layout.quads[q + ((r + 3) & 3)]);
            }
          }
        }
        stencil[std::size_t{base} + k] = t;
      }
    }
  };
  // The second half of the positions beside, the first here.
  std::size_t half = 0;
  while (half < visits.size() && visits[half].end <= count / 2) ++half;
  auto second = beside(two, [&stencils, half, &visits] { stencils(half, visits.size()); });
  stencils(0, half);
  second.get();
}

}  // namespace

ComponentStencils component_stencils(const ComponentPartition& part, const GridLayout& layout,
                                     const Numbering& n, CodingOrder order) {
  const bool general = part.kind == ComponentKind::kUnstructured || part.kind == ComponentKind::kDisk;
  ComponentStencils out;
  if (general && order == CodingOrder::kPatch) {  // its own stencils: none of layout order's are needed
    patch_order(part.schematic, n, layout, 0, out.stencil, out.coding);
    return out;
  }
  out.stencil.assign(layout.vertex_count, {});
  auto& st = out.stencil;
  if (!general) {
    const std::uint32_t a = part.a, rows = layout.vertex_count / std::max(a, 1u);
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

MeshLayout assemble(std::span<const ComponentPartition> parts, std::uint32_t unreferenced,
                    std::optional<CodingOrder> order) {
  MeshLayout out;
  auto shift = [](std::uint32_t v, std::uint32_t base) { return v == kInvalid ? kInvalid : v + base; };
  const bool patch = order == CodingOrder::kPatch;
  // Every component's grid first, so the arrays are sized once: grown by doubling, they touched three
  // times their memory (6 MB of fresh pages decoding mh_base's 153 components, 19k vertices).
  std::vector<Numbering> numbering(parts.size());
  std::vector<GridLayout> grids;
  grids.reserve(parts.size());
  std::size_t quads = 0, vertices = unreferenced;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    grids.push_back(grid_layout(parts[i], numbering[i]));
    quads += grids.back().quads.size();
    vertices += grids.back().vertex_count;
  }
  const bool one = parts.size() == 1;  // its arrays move, not copy (peak memory)
  if (!one) out.quads.reserve(quads);
  if (order) out.stencil.reserve(vertices);
  if (patch) out.coding.reserve(vertices);
  std::uint32_t base = 0;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    GridLayout& g = grids[i];
    const ComponentKind kind = parts[i].kind;
    if (patch && (kind == ComponentKind::kUnstructured || kind == ComponentKind::kDisk)) {
      // Patch order straight into the mesh's arrays, before the quads move (it reads them).
      patch_order(parts[i].schematic, numbering[i], g, base, out.stencil, out.coding);
    } else if (order) {
      ComponentStencils c = component_stencils(parts[i], g, numbering[i], *order);
      if (patch) {
        if (c.coding.empty()) {
          for (std::uint32_t v = 0; v < g.vertex_count; ++v) out.coding.push_back(v + base);
        } else {
          for (std::uint32_t v : c.coding) out.coding.push_back(v + base);
        }
      }
      if (one && out.stencil.empty()) {
        out.stencil = std::move(c.stencil);
        out.stencil.reserve(vertices);
      } else {
        for (Stencil st : c.stencil) {
          for (std::uint32_t* j : st.vertex_fields()) *j = shift(*j, base);
          out.stencil.push_back(st);
        }
      }
    }
    if (one) {
      out.quads = std::move(g.quads);
    } else {
      for (std::uint32_t v : g.quads) out.quads.push_back(v + base);
    }
    base += g.vertex_count;
    g = GridLayout{};  // its memory back before the next component's stencils
  }
  out.vertex_count = base + unreferenced;
  if (!order) return out;
  for (std::uint32_t u = 0; u < unreferenced; ++u) {  // each predicted from the previous vertex
    const std::uint32_t v = base + u;
    out.stencil.push_back({v == 0 ? kInvalid : v - 1, kInvalid, kInvalid, kInvalid});
    if (patch) out.coding.push_back(v);
  }
  return out;
}

void check_stencils(std::span<const Stencil> stencil, std::size_t n) {
  if (stencil.size() != n) throw Error(ErrorCode::kInternal, "geometry: stencil count != vertex count");
  const Words& mask = vertex_word_mask();
  for (std::uint32_t i = 0; i < n; ++i) {
    // j >= i for a field j other than kInvalid, i.e. j + 1 > i with kInvalid wrapping to 0 (and the
    // other fields masked to kInvalid): no branch per field (gathering the fields was 2% of a decode).
    const Words words = std::bit_cast<Words>(stencil[i]);
    std::uint32_t forward = 0;
    for (std::size_t k = 0; k < kWords; ++k)
      forward |= static_cast<std::uint32_t>(((words[k] | ~mask[k]) + 1) > i);
    if (forward) throw Error(ErrorCode::kInternal, "geometry: stencil refers forward");
    if (stencil[i].mirror != kInvalid && stencil[i].mirror_axis > 2)
      throw Error(ErrorCode::kInternal, "geometry: mirror axis out of range");
  }
}

}  // namespace qsp
