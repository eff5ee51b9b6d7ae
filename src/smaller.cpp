// Smaller structured partitions (§7): the greedy path-at-a-time construction, patch merging on the
// schematic, and the mode dispatcher. Every choice is ordered by structure first and then by the
// canonical dart labels of a canonical schematic, so the results are canonical (see smaller.h).
#include "qsp/smaller.h"

#include <algorithm>
#include <queue>
#include <string>
#include <tuple>

#include "qsp/canonical.h"
#include "qsp/error.h"

namespace qsp {
namespace {

[[noreturn]] void internal(const std::string& what) {
  throw Error(ErrorCode::kInternal, "smaller partition: " + what + " (please report this mesh)");
}

bool general(ComponentKind k) { return k == ComponentKind::kUnstructured || k == ComponentKind::kDisk; }

// The general components of `p` relabelled canonically (dart index = canonical label), indexed by
// component id; structured components stay empty. Positions only break ties between roots that
// give equal codes, i.e. between automorphic labellings: any of them yields an isomorphic partition,
// but on a symmetric mesh only positions pick the same one for every numbering of the same mesh,
// which the codec's bytes need. Without positions (empty), all-zero ones: the first tied root.
std::vector<ComponentPartition> canonical_parts(const Adjacency& adj, const Partition& p,
                                                std::span<const float> positions) {
  Partition only_general;
  for (const auto& c : p.components)
    if (general(c.kind)) only_general.components.push_back(c);
  QuadMesh mesh;
  if (positions.size() == 3ull * adj.vertex_count) {
    mesh.positions.assign(positions.begin(), positions.end());
  } else {
    mesh.positions.assign(3ull * adj.vertex_count, 0.0f);
  }
  CanonicalMesh cm = canonicalize(mesh, adj, only_general);
  std::vector<ComponentPartition> out(p.components.size());
  for (auto& c : cm.components) out[c.part.component] = std::move(c.part);
  return out;
}

// ---------------------------------------------------------------------------------------------------
// Greedy (§7): one straight path at a time from an extraordinary vertex, each running until it meets
// an extraordinary vertex, a vertex already on a path, or the boundary.

class Greedy {
 public:
  Greedy(const Adjacency& adj, std::vector<std::uint32_t> rank)
      : adj_(adj),
        rank_(std::move(rank)),
        cut_(adj.halfedge_count(), 0),
        cuts_at_(adj.vertex_count, 0),
        stamp_(adj.vertex_count, 0) {
    for (std::uint32_t h = 4 * adj.face_count; h < adj.halfedge_count(); ++h) mark(h);
    xv_ = extraordinary_vertices(adj);
  }

  std::vector<std::uint32_t> run() {
    // Candidates: every unused interior edge at every extraordinary vertex, best key first.
    for (std::uint32_t x : xv_) push_vertex(x);
    while (!queue_.empty()) {
      const Entry top = queue_.top();
      queue_.pop();
      Entry now;
      if (!evaluate(top.h, now)) continue;
      if (now.red <= 0) continue;  // re-pushed whenever its vertex changes (push_vertex)
      if (now < top) {             // stale: its path got shorter or its vertex needs less
        queue_.push(now);
        continue;
      }
      add_path(top.h);
    }
    // Whatever the queue missed (it should miss nothing): fix every vertex in rank order.
    for (std::uint32_t x : xv_)
      while (need(x, kInvalid, kInvalid) > 0) {
        std::uint32_t best = kInvalid;
        for (std::uint32_t h : ring(x)) {
          Entry e;
          if (evaluate(h, e) && e.red > 0 && (best == kInvalid || rank_[h] < rank_[best])) best = h;
        }
        if (best == kInvalid) internal("no path reduces the need at vertex " + std::to_string(x));
        add_path(best);
      }
    repair_annuli();
    return paths_;
  }

 private:
  struct Entry {
    int red = 0;                 // how much the path lowers the need of its end vertices
    int cost = 0;                // schematic edges it adds (estimate): 1, or 2 if it makes a T vertex
    std::uint32_t length = 0;    // mesh edges along it
    std::uint32_t rank = 0;      // canonical label of the motorcycle dart that starts with h
    std::uint32_t h = kInvalid;  // first half-edge, leaving the extraordinary vertex
    // Larger is better: more reduction, then fewer edges, then shorter, then smaller rank. Shorter
    // first blocks fewer later paths and gives shorter edge lengths (measured: ~1.5% fewer schematic
    // edges and ~7% fewer topology bytes on ../shared/meshes than ignoring length or longest first).
    bool operator<(const Entry& o) const {
      return std::make_tuple(red, -cost, o.length, o.rank, o.h) <
             std::make_tuple(o.red, -o.cost, length, rank, h);
    }
  };
  struct Trace {
    std::uint32_t last = kInvalid, length = 0;
    bool self = false;  // stopped on its own track
  };

  bool is_boundary_edge(std::uint32_t h) const {
    return adj_.is_exterior(h) || adj_.is_exterior(adj_.twin[h]);
  }
  std::uint32_t straight(std::uint32_t h) const { return adj_.next(adj_.twin[adj_.next(h)]); }

  void mark(std::uint32_t h) {
    if (cut_[h]) return;
    cut_[h] = cut_[adj_.twin[h]] = 1;
    ++cuts_at_[adj_.origin[h]];
    ++cuts_at_[adj_.dest(h)];
  }

  // Outgoing half-edges of v, clockwise.
  std::vector<std::uint32_t> ring(std::uint32_t v) const {
    std::vector<std::uint32_t> out;
    const std::uint32_t h0 = adj_.vertex_halfedge[v];
    std::uint32_t h = h0;
    do {
      out.push_back(h);
      h = adj_.rotate(h);
    } while (h != h0 && out.size() <= adj_.valence[v]);
    return out;
  }

  // Fewest further edges at v that leave no two consecutive unused edges (no patch sector of 3+
  // faces) and, inside, at least two used edges (a schematic vertex needs degree >= 2), with the
  // half-edges a and b (leaving v) counted as used.
  int need(std::uint32_t v, std::uint32_t a, std::uint32_t b) const {
    const std::vector<std::uint32_t> r = ring(v);
    const int d = static_cast<int>(r.size());
    int used = 0, first = -1;
    std::vector<std::uint8_t> u(d);
    for (int i = 0; i < d; ++i) {
      u[i] = cut_[r[i]] || r[i] == a || r[i] == b;
      if (u[i]) {
        ++used;
        if (first < 0) first = i;
      }
    }
    int n = 0;
    if (used == 0) {
      n = (d + 1) / 2;
    } else {
      int run = 0;
      for (int k = 1; k <= d; ++k) {
        const int i = (first + k) % d;
        if (u[i]) {
          n += run / 2;
          run = 0;
        } else {
          ++run;
        }
      }
    }
    if (!adj_.boundary[v]) n = std::max(n, 2 - used);
    return n;
  }

  // True if v is already a schematic vertex: nonzero deficiency or a patch sector of one face.
  bool is_schematic_vertex(std::uint32_t v) const {
    if (adj_.deficiency(v) != 0) return true;
    const std::vector<std::uint32_t> r = ring(v);
    const std::size_t d = r.size();
    for (std::size_t i = 0; i < d; ++i) {
      // Between r[i] and r[i+1] lies the face right of r[i]: a one-face sector if both are cut.
      if (cut_[r[i]] && cut_[r[(i + 1) % d]] && !adj_.is_exterior(adj_.twin[r[i]])) return true;
    }
    return false;
  }

  // Follows h straight on until a stop; does not change anything.
  Trace trace(std::uint32_t h) {
    Trace t;
    ++epoch_;
    stamp_[adj_.origin[h]] = epoch_;
    std::uint32_t g = h, len = 1;
    for (;;) {
      const std::uint32_t w = adj_.dest(g);
      if (adj_.extraordinary(w) || adj_.boundary[w] || cuts_at_[w] > 0) break;
      if (stamp_[w] == epoch_) {
        t.self = true;
        break;
      }
      stamp_[w] = epoch_;
      g = straight(g);
      if (++len > adj_.halfedge_count()) internal("path does not end");
    }
    t.last = g;
    t.length = len;
    return t;
  }

  bool evaluate(std::uint32_t h, Entry& e) {
    if (cut_[h] || is_boundary_edge(h)) return false;
    const std::uint32_t x = adj_.origin[h];
    const Trace t = trace(h);
    const std::uint32_t y = adj_.dest(t.last), in = adj_.twin[t.last];
    e.h = h;
    e.length = t.length;
    e.rank = rank_[h];
    if (adj_.extraordinary(y) && !t.self) {
      if (y == x) {
        e.red = need(x, kInvalid, kInvalid) - need(x, h, in);
      } else {
        e.red = need(x, kInvalid, kInvalid) + need(y, kInvalid, kInvalid) - need(x, h, kInvalid) -
                need(y, in, kInvalid);
      }
      e.cost = 1;
    } else {
      e.red = need(x, kInvalid, kInvalid) - need(x, h, kInvalid);
      e.cost = (!t.self && is_schematic_vertex(y)) ? 1 : 2;
    }
    return true;
  }

  void push_vertex(std::uint32_t x) {
    for (std::uint32_t h : ring(x)) {
      Entry e;
      if (evaluate(h, e) && e.red > 0) queue_.push(e);
    }
  }

  void add_path(std::uint32_t h) {
    const Trace t = trace(h);
    const std::uint32_t x = adj_.origin[h], y = adj_.dest(t.last);
    std::uint32_t g = h;
    for (;;) {
      mark(g);
      paths_.push_back(g);
      if (g == t.last) break;
      g = straight(g);
    }
    push_vertex(x);
    if (adj_.extraordinary(y) && y != x) push_vertex(y);
  }

  // A region whose boundary has no corner is an annulus (every sector has two faces, so Lemma 1
  // gives Euler characteristic 0). Its boundary has an extraordinary vertex whose unused middle edge
  // points into it (§5's argument); the straight path from there crosses it to its other side.
  void repair_annuli() {
    const std::uint32_t nf = adj_.face_count;
    for (int round = 0; round < 64; ++round) {
      std::vector<std::uint32_t> region(nf, kInvalid);
      std::uint32_t regions = 0;
      std::vector<std::uint32_t> stack;
      for (std::uint32_t f0 = 0; f0 < nf; ++f0) {
        if (region[f0] != kInvalid) continue;
        region[f0] = regions;
        stack.push_back(f0);
        while (!stack.empty()) {
          const std::uint32_t f = stack.back();
          stack.pop_back();
          for (std::uint32_t i = 0; i < 4; ++i) {
            const std::uint32_t h = 4 * f + i;
            if (cut_[h]) continue;
            const std::uint32_t g = adj_.face(adj_.twin[h]);
            if (region[g] == kInvalid) {
              region[g] = regions;
              stack.push_back(g);
            }
          }
        }
        ++regions;
      }
      std::vector<std::uint32_t> corners(regions, 0);
      for (std::uint32_t h = 0; h < 4 * nf; ++h) {
        if (!cut_[h]) continue;
        std::uint32_t g = adj_.next(h), faces = 1;
        while (!cut_[g]) {
          g = adj_.next(adj_.twin[g]);
          ++faces;
        }
        if (faces == 1) ++corners[region[h >> 2]];
        if (faces > 2)
          internal("vertex " + std::to_string(adj_.origin[g]) + " keeps a sector of " +
                   std::to_string(faces) + " faces");
      }
      // Best (smallest rank) launching edge per annulus; regions of components without extraordinary
      // vertices are whole structured components and stay as they are.
      std::vector<std::uint32_t> launch(regions, kInvalid);
      bool any = false;
      for (std::uint32_t x : xv_)
        for (std::uint32_t h : ring(x)) {
          if (cut_[h] || is_boundary_edge(h)) continue;
          const std::uint32_t r = region[h >> 2];
          if (corners[r] != 0) continue;
          if (launch[r] == kInvalid || rank_[h] < rank_[launch[r]]) launch[r] = h;
        }
      for (std::uint32_t r = 0; r < regions; ++r)
        if (launch[r] != kInvalid) {
          add_path(launch[r]);
          any = true;
        }
      if (!any) return;
    }
    internal("annulus repair does not converge");
  }

  const Adjacency& adj_;
  std::vector<std::uint32_t>
      rank_;  // per half-edge: canonical rank (only those at extraordinary vertices matter)
  std::vector<std::uint8_t> cut_;       // per half-edge: its edge is cut (boundary or on a path)
  std::vector<std::uint32_t> cuts_at_;  // per vertex: cut edges incident to it
  std::vector<std::uint32_t> stamp_;    // per vertex: last trace that passed it
  std::uint32_t epoch_ = 0;
  std::vector<std::uint32_t> xv_;
  std::vector<std::uint32_t> paths_;  // chosen cut half-edges, in order
  std::priority_queue<Entry> queue_;
};

// Per half-edge leaving an extraordinary vertex: the canonical label of the motorcycle dart it starts
// (every such edge starts a particle, so it starts a dart). Others get kInvalid.
std::vector<std::uint32_t> canonical_ranks(const Adjacency& adj, const Partition& motorcycle,
                                           std::span<const float> positions) {
  std::vector<std::uint32_t> rank(adj.halfedge_count(), kInvalid);
  const std::vector<ComponentPartition> canon = canonical_parts(adj, motorcycle, positions);
  for (const auto& part : canon) {
    const Schematic& s = part.schematic;
    for (std::uint32_t d = 0; d < s.dart_count(); ++d) rank[s.dart_halfedge[d]] = d;
  }
  return rank;
}

// ---------------------------------------------------------------------------------------------------
// Merging (§7) on one schematic whose darts are in canonical order. Returns the removed edges.

class Merger {
 public:
  explicit Merger(const Schematic& s)
      : s_(s),
        next_(s.dart_next),
        prev_(s.dart_prev),
        face_(s.dart_face),
        corner_(s.dart_corner),
        alive_(s.dart_count(), 1),
        degree_(s.vertex_count, 0),
        corners_at_(s.vertex_count, 0),
        stamp_(s.vertex_count, 0) {
    for (std::uint32_t d = 0; d < s.dart_count(); ++d) {
      ++degree_[s.dart_vertex[d]];
      corners_at_[s.dart_vertex[d]] += corner_[d];
    }
  }

  std::vector<std::uint32_t> run() {
    for (std::uint32_t d = 0; d < s_.dart_count(); ++d) push(d);
    while (!queue_.empty()) {
      const auto [score, neg_rank] = queue_.top();
      queue_.pop();
      const std::uint32_t d = static_cast<std::uint32_t>(-neg_rank);
      Side side;
      if (!match(d, side)) continue;
      if (side.score < score) {
        queue_.emplace(side.score, neg_rank);
        continue;
      }
      apply(side);
    }
    std::vector<std::uint32_t> removed;
    for (std::uint32_t e = 0; e < s_.edge_count(); ++e)
      if (!alive_[2 * e]) removed.push_back(e);
    return removed;
  }

 private:
  struct Side {
    std::vector<std::uint32_t> darts;  // d1..dk along patch P, from corner u to corner v
    std::uint32_t end = kInvalid;      // the corner dart of P after dk (leaves v)
    int score = 0;                     // schematic vertices the merge dissolves (0..2)
  };

  void push(std::uint32_t d) {
    Side side;
    if (match(d, side)) queue_.emplace(side.score, -static_cast<std::int64_t>(d));
  }

  // Is the side of d's patch starting at d also a whole side of the patch across it, with the two
  // patches touching nowhere else? Then their union is one grid.
  bool match(std::uint32_t d1, Side& side) {
    if (!alive_[d1] || !corner_[d1] || s_.face_hole[face_[d1]]) return false;
    const std::uint32_t p = face_[d1];
    side.darts.clear();
    std::uint32_t d = d1;
    do {
      side.darts.push_back(d);
      d = next_[d];
      if (side.darts.size() > s_.dart_count()) return false;
    } while (!corner_[d]);
    side.end = d;
    const std::size_t k = side.darts.size();
    const std::uint32_t tk = side.darts[k - 1] ^ 1, q = face_[tk];
    if (q == p || s_.face_hole[q] || !corner_[tk]) return false;
    for (std::size_t i = k - 1; i >= 1; --i) {
      const std::uint32_t t = side.darts[i] ^ 1, t_prev = side.darts[i - 1] ^ 1;
      if (next_[t] != t_prev || corner_[t_prev]) return false;
    }
    if (!corner_[next_[side.darts[0] ^ 1]]) return false;
    const std::uint32_t u = s_.dart_vertex[d1], v = s_.dart_vertex[side.end];
    if (u == v) return false;
    // Touching elsewhere: another shared edge (the union would be an annulus) or a shared vertex
    // (a pinch); u and v must each appear once on either patch.
    ++epoch_;
    for (std::uint32_t x : side.darts) stamp_[s_.dart_vertex[x]] = epoch_;
    stamp_[v] = epoch_;
    const std::uint32_t mark = epoch_;
    ++epoch_;
    std::uint32_t e = d1, ends = 0;
    do {
      if (face_[e ^ 1] == q && std::find(side.darts.begin(), side.darts.end(), e) == side.darts.end())
        return false;
      const std::uint32_t w = s_.dart_vertex[e];
      ends += w == u || w == v;
      if (stamp_[w] != mark) stamp_[w] = epoch_;
      e = next_[e];
    } while (e != d1);
    e = tk;
    do {
      const std::uint32_t w = s_.dart_vertex[e];
      ends += w == u || w == v;
      if (stamp_[w] == epoch_) return false;
      e = next_[e];
    } while (e != tk);
    if (ends != 4) return false;
    side.score = (degree_[u] - 1 == 2 && corners_at_[u] == 2) + (degree_[v] - 1 == 2 && corners_at_[v] == 2);
    return true;
  }

  void apply(const Side& side) {
    const std::size_t k = side.darts.size();
    const std::uint32_t d1 = side.darts[0], b = side.end, t1 = d1 ^ 1, tk = side.darts[k - 1] ^ 1;
    const std::uint32_t p = face_[d1], a = prev_[d1], g = next_[t1], c = prev_[tk];
    const std::uint32_t u = s_.dart_vertex[d1], v = s_.dart_vertex[b];
    next_[a] = g, prev_[g] = a;
    next_[c] = b, prev_[b] = c;
    // u and v stop being corners: each now sees one face of P and one of Q, i.e. a straight side.
    corner_[g] = 0, corner_[b] = 0;
    corners_at_[u] -= 2, corners_at_[v] -= 2;
    for (std::uint32_t x : side.darts) {
      alive_[x] = alive_[x ^ 1] = 0;
      --degree_[s_.dart_vertex[x]];
      --degree_[s_.dart_vertex[x ^ 1]];
    }
    std::uint32_t e = g;
    do {
      face_[e] = p;
      e = next_[e];
    } while (e != g);
    // New candidates: the merged patch's sides and every side at u or v (their scores changed).
    e = g;
    do {
      push(e);
      e = next_[e];
    } while (e != g);
    for (std::uint32_t w : {u, v}) {
      const std::uint32_t start = w == u ? g : b;
      std::uint32_t r = start;
      do {
        std::uint32_t f = r;
        do {
          push(f);
          f = next_[f];
        } while (f != r);
        r = next_[r ^ 1];
      } while (r != start);
    }
  }

  const Schematic& s_;
  std::vector<std::uint32_t> next_, prev_, face_;
  std::vector<std::uint8_t> corner_, alive_;
  std::vector<std::uint32_t> degree_, corners_at_;  // per schematic vertex
  std::vector<std::uint32_t> stamp_;
  std::uint32_t epoch_ = 0;
  std::priority_queue<std::pair<int, std::int64_t>> queue_;  // (score, -first dart): best, then smallest
};

// Cut half-edges of a partition's input set as a per-half-edge flag (boundary included).
std::vector<std::uint8_t> cut_flags(const Adjacency& adj, std::span<const std::uint32_t> cuts) {
  std::vector<std::uint8_t> cut(adj.halfedge_count(), 0);
  for (std::uint32_t h = 4 * adj.face_count; h < adj.halfedge_count(); ++h) cut[h] = cut[adj.twin[h]] = 1;
  for (std::uint32_t h : cuts) {
    if (h >= adj.halfedge_count()) internal("cut half-edge out of range");
    cut[h] = cut[adj.twin[h]] = 1;
  }
  return cut;
}

std::vector<std::uint32_t> cut_list(const Adjacency& adj, const std::vector<std::uint8_t>& cut) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t h = 0; h < 4 * adj.face_count; ++h)
    if (cut[h] && !adj.is_exterior(adj.twin[h]) && h < adj.twin[h]) out.push_back(h);
  return out;
}

}  // namespace

const char* partition_mode_name(PartitionMode mode) noexcept {
  switch (mode) {
    case PartitionMode::kMotorcycle:
      return "motorcycle";
    case PartitionMode::kGreedy:
      return "greedy";
    case PartitionMode::kMerge:
      return "merge";
  }
  return "?";
}

bool parse_partition_mode(std::string_view name, PartitionMode& out) noexcept {
  for (PartitionMode m : {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge})
    if (name == partition_mode_name(m)) {
      out = m;
      return true;
    }
  return false;
}

std::vector<std::uint32_t> greedy_cuts(const Adjacency& adj, std::span<const float> positions) {
  const Partition motorcycle = partition_motorcycle(adj);
  Greedy g(adj, canonical_ranks(adj, motorcycle, positions));
  return g.run();
}

std::vector<std::uint32_t> merge_cuts(const Adjacency& adj, std::span<const std::uint32_t> cuts,
                                      std::span<const float> positions) {
  const Partition before = partition_from_cuts(adj, cuts);
  std::vector<std::uint8_t> cut = cut_flags(adj, cuts);
  const std::vector<std::uint8_t> original = cut;
  std::vector<std::uint8_t> is_x(adj.vertex_count, 0);
  for (const auto& part : canonical_parts(adj, before, positions)) {
    const Schematic& s = part.schematic;
    if (s.dart_count() == 0) continue;
    for (std::uint32_t v : s.vertex_mesh) is_x[v] = 1;
    for (std::uint32_t e : Merger(s).run()) {
      // The edge's mesh path: from its first half-edge along the cut set to the next schematic vertex.
      std::uint32_t h = s.dart_halfedge[2 * e];
      for (std::uint32_t guard = 0;; ++guard) {
        if (guard > adj.halfedge_count() || adj.is_exterior(h) || adj.is_exterior(adj.twin[h]))
          internal("merged edge path leaves the interior");
        cut[h] = cut[adj.twin[h]] = 0;
        if (is_x[adj.dest(h)]) break;
        std::uint32_t g = adj.next(h);
        while (!original[g]) g = adj.next(adj.twin[g]);
        h = g;
      }
    }
  }
  return cut_list(adj, cut);
}

Partition partition(const Adjacency& adj, PartitionMode mode, std::span<const float> positions, bool tiling) {
  const std::vector<std::uint32_t> motorcycle = trace_motorcycles(adj, extraordinary_vertices(adj)).traced;
  if (mode == PartitionMode::kMotorcycle) return partition_from_cuts(adj, motorcycle, tiling);
  std::vector<std::uint32_t> cuts = motorcycle;
  if (mode == PartitionMode::kGreedy) {
    try {
      std::vector<std::uint32_t> g = greedy_cuts(adj, positions);
      (void)partition_from_cuts(adj, g);  // validates; throws if the construction went wrong
      cuts = std::move(g);
    } catch (const Error& e) {
      if (e.code() != ErrorCode::kInternal) throw;
    }
  }
  try {
    return partition_from_cuts(adj, merge_cuts(adj, cuts, positions));
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInternal) throw;
  }
  return partition_from_cuts(adj, cuts);
}

PartitionSize partition_size(const Partition& p) {
  PartitionSize z;
  for (const auto& c : p.components) {
    if (!general(c.kind)) {
      ++z.patches;
      continue;
    }
    z.vertices += c.schematic.vertex_count;
    z.edges += c.schematic.edge_count();
    z.patches += c.schematic.patch_count();
  }
  return z;
}

}  // namespace qsp
