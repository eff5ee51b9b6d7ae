// The topology section: every component's TopologyCode, entropy-coded stream type by stream type
// (format-spec/qsp_format.md, "Topology section"). Encoder and decoder run the same traversal model,
// so each symbol is coded relative to what the decoder already knows:
//  - next_ref: the dart's next is a new edge, or closes the rotation around its end vertex, or closes
//    its own face, or else (rare) any other dart without predecessor, by rank;
//  - corners: face by face, exactly four per patch (forced symbols cost nothing), in the context of
//    the origin vertex's degree and the corners already known around it;
//  - edge lengths: opposite sides of a patch have equal length, so a length that the known ones
//    determine is not stored at all.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "codec_sections.h"
#include "entropy.h"
#include "order_set.h"
#include "qsp/error.h"

namespace qsp {
namespace {

[[noreturn]] void fail(ErrorCode code, const std::string& what) { throw Error(code, what); }

// The traversal state shared by encoder and decoder: darts labelled so far, their `next` links, and
// for the two kinds of partial orbits (face chains along next, vertex paths along sigma(d) =
// next(twin(d))) the other end and length of each path, kept at both ends.
struct Traversal {
  std::vector<std::uint32_t> next, prev;
  std::vector<std::uint32_t> fend, flen, vend, vlen;
  OrderSet pool;  // darts without a predecessor yet, by label

  std::uint32_t labelled() const { return static_cast<std::uint32_t>(next.size()); }
  std::uint32_t add_edge() {
    std::uint32_t d = labelled();
    for (std::uint32_t x = d; x < d + 2; ++x) {
      next.push_back(kInvalid);
      prev.push_back(kInvalid);
      fend.push_back(x);
      flen.push_back(1);
      vend.push_back(x);
      vlen.push_back(1);
      pool.reserve(x + 1);
      pool.insert(x);
    }
    return d;
  }
  // Sets next(i) = z; i has no next yet and z no predecessor yet.
  void link(std::uint32_t i, std::uint32_t z) {
    next[i] = z;
    prev[z] = i;
    pool.erase(z);
    join(fend, flen, i, z);
    join(vend, vlen, i ^ 1u, z);  // sigma(twin(i)) = next(i) = z
  }
  static void join(std::vector<std::uint32_t>& end, std::vector<std::uint32_t>& len, std::uint32_t tail,
                   std::uint32_t head) {
    std::uint32_t h = end[tail], t = end[head];
    if (h == head) return;  // closes a cycle: no endpoints left
    end[h] = t;
    end[t] = h;
    len[h] = len[t] = len[tail] + len[head];
  }
};

constexpr std::uint32_t cap(std::uint32_t v, std::uint32_t hi) { return v < hi ? v : hi; }

// All adaptive models of the topology section, in one place so encoder and decoder share them.
struct Models {
  std::array<BitModel, 3> kind;
  IntModel size_a, size_b, twist;
  std::array<BitModel, 5 * 5> is_new;     // by face chain length, vertex path length (capped)
  std::array<BitModel, 5 * 5> is_vertex;  // closes the rotation around its end vertex
  std::array<BitModel, 5 * 5> is_face;    // closes its own face
  BitModel is_newest;                     // the most recently labelled dart without predecessor
  IntModel other_step;                    // else: zigzag of its pool rank minus the visited dart's
  IntModel hole_count;                    // per component
  std::array<BitModel, 4> is_hole;        // by face size - 4 (capped), while holes are left
  std::array<BitModel, 5 * 4 * 3 * 3> corner;
  std::array<IntModel, 2> length;  // interior edge, edge on a hole
};

// The most recently labelled dart without predecessor other than the two candidates; the pool holds
// at least one such dart whenever it is asked for.
std::uint32_t newest_other(const Traversal& t, std::uint32_t vc, std::uint32_t fc) {
  std::uint32_t r = t.pool.size() - 1;
  for (;;) {
    std::uint32_t z = t.pool.select(r);
    if (z != vc && z != fc) return z;
    if (r == 0) return kInvalid;
    --r;
  }
}

std::uint32_t chain_context(const Traversal& t, std::uint32_t i) {
  return 5 * (cap(t.flen[i], 5) - 1) + (cap(t.vlen[i ^ 1u], 5) - 1);
}

// What a component's darts look like once next is complete: faces and vertices as orbits.
struct Orbits {
  std::vector<std::uint32_t> face_of, face_first, face_size;
  std::vector<std::uint32_t> vertex_of, vertex_degree;
};

Orbits orbits(const std::vector<std::uint32_t>& next) {
  Orbits o;
  auto n = static_cast<std::uint32_t>(next.size());
  o.face_of.assign(n, kInvalid);
  o.vertex_of.assign(n, kInvalid);
  for (std::uint32_t d = 0; d < n; ++d) {
    if (o.face_of[d] == kInvalid) {
      auto f = static_cast<std::uint32_t>(o.face_first.size());
      std::uint32_t size = 0;
      for (std::uint32_t x = d; o.face_of[x] == kInvalid; x = next[x]) {
        o.face_of[x] = f;
        ++size;
      }
      o.face_first.push_back(d);
      o.face_size.push_back(size);
    }
    if (o.vertex_of[d] == kInvalid) {
      auto v = static_cast<std::uint32_t>(o.vertex_degree.size());
      std::uint32_t deg = 0;
      for (std::uint32_t x = d; o.vertex_of[x] == kInvalid; x = next[x ^ 1u]) {
        o.vertex_of[x] = v;
        ++deg;
      }
      o.vertex_degree.push_back(deg);
    }
  }
  return o;
}

// Per component, once next is known: which darts start a corner, and the bookkeeping of the context.
struct CornerState {
  Orbits o;
  std::vector<std::uint8_t> hole;               // per face
  std::vector<std::uint8_t> corner;             // per dart
  std::vector<std::uint8_t> v_corner, v_plain;  // per vertex: corners / non-corners known so far
};

std::uint32_t corner_context(const CornerState& s, std::uint32_t d, std::uint32_t needed,
                             std::uint32_t remaining) {
  std::uint32_t v = s.o.vertex_of[d];
  std::uint32_t deg = cap(std::max<std::uint32_t>(s.o.vertex_degree[v], 2), 6) - 2;  // 0..4
  std::uint32_t slack = cap(remaining - needed, 3) - 1;                              // 0..2
  return ((deg * 4 + cap(s.v_corner[v], 3)) * 3 + cap(s.v_plain[v], 2)) * 3 + slack;
}

void mark_corner(CornerState& s, std::uint32_t d, bool is_corner) {
  s.corner[d] = is_corner ? 1 : 0;
  std::uint32_t v = s.o.vertex_of[d];
  auto& c = is_corner ? s.v_corner : s.v_plain;
  if (c[v] < 255) ++c[v];
}

// Every dart of a hole is a non-corner: known to the corner contexts before any corner is coded.
void mark_holes(CornerState& s, const std::vector<std::uint32_t>& next) {
  for (std::uint32_t f = 0; f < s.o.face_first.size(); ++f) {
    if (!s.hole[f]) continue;
    std::uint32_t x = s.o.face_first[f];
    do {
      mark_corner(s, x, false);
      x = next[x];
    } while (x != s.o.face_first[f]);
  }
}

std::string near(const RangeDecoder& dec) {
  return " (near byte offset " + std::to_string(dec.offset()) + ")";
}

// Patch side constraints: sum of lengths on side 0 == side 2, side 1 == side 3.
struct LengthSolver {
  struct Term {
    std::uint32_t edge;  // or constraint, in by_edge
    std::int32_t coef;
  };
  // Flat arrays, not a vector per constraint and per edge: their allocations were a third of coding
  // the topology of a mesh of many small patches (mh_base: 3,000 constraints).
  std::vector<Term> terms;              // constraint c's terms: [first[c], first[c + 1])
  std::vector<std::uint32_t> first{0};  // per constraint, and one past the last
  std::vector<Term> by_edge;  // edge e's constraints with its coefficient: [edge_first[e], edge_first[e + 1])
  std::vector<std::uint32_t> edge_first;  // per edge, and one past the last
  std::vector<std::uint32_t> unknown;     // per constraint
  std::vector<std::int64_t> known_sum;    // per constraint
  std::vector<std::uint8_t> known;        // per edge

  LengthSolver(const Orbits& o, const std::vector<std::uint8_t>& hole,
               const std::vector<std::uint8_t>& corner, const std::vector<std::uint32_t>& next,
               std::uint32_t edges) {
    known.assign(edges, 0);
    std::vector<Term> a, b;
    for (std::uint32_t f = 0; f < o.face_first.size(); ++f) {
      if (hole[f]) continue;
      std::uint32_t start = o.face_first[f];
      while (!corner[start]) start = next[start];
      a.clear();
      b.clear();
      int side = -1;
      std::uint32_t x = start;
      do {
        if (corner[x]) ++side;
        std::uint32_t e = x >> 1;
        if (side == 0) a.push_back({e, 1});
        if (side == 2) a.push_back({e, -1});
        if (side == 1) b.push_back({e, 1});
        if (side == 3) b.push_back({e, -1});
        x = next[x];
      } while (x != start);
      add(a);
      add(b);
    }
    const std::size_t constraints = first.size() - 1;
    // Each edge's constraints in constraint order.
    edge_first.assign(std::size_t{edges} + 1, 0);
    for (const Term& t : terms) ++edge_first[t.edge + 1];
    for (std::uint32_t e = 0; e < edges; ++e) edge_first[e + 1] += edge_first[e];
    by_edge.resize(terms.size());
    std::vector<std::uint32_t> fill(edge_first.begin(), edge_first.end() - 1);
    for (std::uint32_t c = 0; c < constraints; ++c)
      for (std::uint32_t k = first[c]; k < first[c + 1]; ++k)
        by_edge[fill[terms[k].edge]++] = {c, terms[k].coef};
    unknown.resize(constraints);
    known_sum.assign(constraints, 0);
    for (std::size_t c = 0; c < constraints; ++c) unknown[c] = first[c + 1] - first[c];
  }
  // Appends the constraint "the terms sum to 0", its terms merged by edge (those that cancel left out);
  // none if all cancel.
  void add(std::vector<Term>& t) {
    std::sort(t.begin(), t.end(), [](const Term& p, const Term& q) { return p.edge < q.edge; });
    const std::size_t from = terms.size();
    for (const Term& x : t) {
      if (terms.size() > from && terms.back().edge == x.edge) {
        terms.back().coef += x.coef;
      } else {
        terms.push_back(x);
      }
    }
    terms.erase(std::remove_if(terms.begin() + static_cast<std::ptrdiff_t>(from), terms.end(),
                               [](const Term& x) { return x.coef == 0; }),
                terms.end());
    if (terms.size() > from) first.push_back(static_cast<std::uint32_t>(terms.size()));
  }
  // Records length[e] and derives every length that becomes determined, writing it into `length`.
  // A derived length that is not a positive integer <= max_length, or a fully known constraint that
  // does not hold, throws Error(kFormat) (kInternal when `encoding`: the code itself was wrong).
  void set(std::uint32_t e, std::vector<std::uint32_t>& length, std::uint64_t max_length, bool encoding,
           std::uint64_t offset) {
    std::vector<std::uint32_t> queue{e};
    known[e] = 1;
    while (!queue.empty()) {
      std::uint32_t x = queue.back();
      queue.pop_back();
      for (std::uint32_t k = edge_first[x]; k < edge_first[x + 1]; ++k) {
        const Term& ct = by_edge[k];
        std::uint32_t c = ct.edge;
        known_sum[c] += std::int64_t{ct.coef} * length[x];
        if (--unknown[c] == 0) {
          if (known_sum[c] != 0) bad(encoding, "opposite sides of a patch differ in length", offset);
          continue;
        }
        if (unknown[c] != 1) continue;
        for (std::uint32_t k2 = first[c]; k2 < first[c + 1]; ++k2) {
          const Term& t = terms[k2];
          if (known[t.edge]) continue;
          std::int64_t value = -known_sum[c] / t.coef;
          if (value * t.coef != -known_sum[c] || value < 1 ||
              static_cast<std::uint64_t>(value) > max_length) {
            bad(encoding, "patch sides imply an impossible edge length", offset);
          }
          if (encoding && length[t.edge] != value) bad(true, "patch sides differ in length", offset);
          length[t.edge] = static_cast<std::uint32_t>(value);
          known[t.edge] = 1;
          queue.push_back(t.edge);
        }
      }
    }
  }
  [[noreturn]] static void bad(bool encoding, const std::string& what, std::uint64_t offset) {
    if (encoding) fail(ErrorCode::kInternal, "encode_topology: " + what);
    fail(ErrorCode::kFormat, "topology: " + what + " (near byte offset " + std::to_string(offset) + ")");
  }
};

bool has_schematic(ComponentKind k) { return k == ComponentKind::kUnstructured || k == ComponentKind::kDisk; }

}  // namespace

std::string encode_topology(std::span<const TopologyCode> codes) {
  std::string out;
  RangeEncoder enc(out);
  Models m;
  for (const TopologyCode& c : codes) {
    auto k = static_cast<unsigned>(c.kind);
    if (k > 3) fail(ErrorCode::kInternal, "encode_topology: bad component kind");
    enc.encode_bit(m.kind[0], k >> 1);
    enc.encode_bit(m.kind[1 + (k >> 1)], k & 1u);
    if (!has_schematic(c.kind)) {
      m.size_a.encode(enc, c.a);
      m.size_b.encode(enc, c.b);
      if (c.kind == ComponentKind::kTorus) m.twist.encode(enc, c.twist);
    }
  }
  // next_ref streams.
  std::vector<Traversal> trav(codes.size());
  for (std::size_t ci = 0; ci < codes.size(); ++ci) {
    const TopologyCode& c = codes[ci];
    if (!has_schematic(c.kind)) continue;
    Traversal& t = trav[ci];
    t.add_edge();
    for (std::uint32_t i = 0; i < t.labelled(); ++i) {
      if (i >= c.next_ref.size()) fail(ErrorCode::kInternal, "encode_topology: next_ref too short");
      std::uint32_t ctx = chain_context(t, i);
      std::uint32_t k = c.next_ref[i];
      if (k == 0) {
        enc.encode_bit(m.is_new[ctx], 1);
        t.link(i, t.add_edge());
        continue;
      }
      if (k > t.pool.size()) fail(ErrorCode::kInternal, "encode_topology: next_ref out of range");
      enc.encode_bit(m.is_new[ctx], 0);
      std::uint32_t z = t.pool.select(k - 1);
      std::uint32_t vc = t.vend[i ^ 1u], fc = t.fend[i];
      enc.encode_bit(m.is_vertex[ctx], z == vc ? 1 : 0);
      if (z != vc) {
        if (fc != vc) enc.encode_bit(m.is_face[ctx], z == fc ? 1 : 0);
        if (z != fc) {
          std::uint32_t newest = newest_other(t, vc, fc);
          enc.encode_bit(m.is_newest, z == newest ? 1 : 0);
          if (z != newest) m.other_step.encode(enc, zigzag(std::int64_t{t.pool.rank(z)} - t.pool.rank(i)));
        }
      }
      t.link(i, z);
    }
    if (c.next_ref.size() != t.labelled()) fail(ErrorCode::kInternal, "encode_topology: next_ref too long");
    if (c.corner.size() != t.labelled() || c.edge_length.size() * 2 != t.labelled()) {
      fail(ErrorCode::kInternal, "encode_topology: stream sizes disagree");
    }
  }
  // Holes, then corners.
  std::vector<CornerState> cs(codes.size());
  for (std::size_t ci = 0; ci < codes.size(); ++ci) {
    if (!has_schematic(codes[ci].kind)) continue;
    CornerState& s = cs[ci];
    s.o = orbits(trav[ci].next);
    s.corner.assign(trav[ci].labelled(), 0);
    s.v_corner.assign(s.o.vertex_degree.size(), 0);
    s.v_plain.assign(s.o.vertex_degree.size(), 0);
    s.hole.assign(s.o.face_first.size(), 0);
    std::uint32_t holes = 0;
    for (std::uint32_t f = 0; f < s.o.face_first.size(); ++f) {
      std::uint32_t corners = 0;
      std::uint32_t x = s.o.face_first[f];
      do {
        corners += codes[ci].corner[x] ? 1 : 0;
        x = trav[ci].next[x];
      } while (x != s.o.face_first[f]);
      if (corners != 0 && corners != 4) fail(ErrorCode::kInternal, "encode_topology: face with bad corners");
      s.hole[f] = corners == 0;
      holes += s.hole[f];
    }
    // Most components have no hole: their count says so and no face needs a flag.
    m.hole_count.encode(enc, holes);
    for (std::uint32_t f = 0, left = holes; f < s.o.face_first.size() && left > 0; ++f) {
      if (s.o.face_size[f] < 4) {
        if (!s.hole[f]) fail(ErrorCode::kInternal, "encode_topology: patch with < 4 darts");
        --left;
        continue;
      }
      enc.encode_bit(m.is_hole[cap(s.o.face_size[f] - 4, 3)], s.hole[f]);
      left -= s.hole[f];
    }
    mark_holes(s, trav[ci].next);
  }
  for (std::size_t ci = 0; ci < codes.size(); ++ci) {
    if (!has_schematic(codes[ci].kind)) continue;
    CornerState& s = cs[ci];
    for (std::uint32_t f = 0; f < s.o.face_first.size(); ++f) {
      if (s.hole[f]) continue;
      std::uint32_t needed = 4, remaining = s.o.face_size[f];
      std::uint32_t x = s.o.face_first[f];
      do {
        bool is_corner = codes[ci].corner[x] != 0;
        if (needed != 0 && needed != remaining) {
          enc.encode_bit(m.corner[corner_context(s, x, needed, remaining)], is_corner ? 1 : 0);
        }
        mark_corner(s, x, is_corner);
        needed -= is_corner ? 1 : 0;
        --remaining;
        x = trav[ci].next[x];
      } while (x != s.o.face_first[f]);
    }
  }
  // Edge lengths.
  for (std::size_t ci = 0; ci < codes.size(); ++ci) {
    const TopologyCode& c = codes[ci];
    if (!has_schematic(c.kind)) continue;
    const CornerState& s = cs[ci];
    auto edges = static_cast<std::uint32_t>(c.edge_length.size());
    LengthSolver solver(s.o, s.hole, cs[ci].corner, trav[ci].next, edges);
    std::vector<std::uint32_t> length(c.edge_length.begin(), c.edge_length.end());
    for (std::uint32_t e = 0; e < edges; ++e) {
      if (solver.known[e]) continue;
      if (length[e] < 1 || length[e] == 0xFFFFFFFFu)
        fail(ErrorCode::kInternal, "encode_topology: bad length");
      bool on_hole = s.hole[s.o.face_of[2 * e]] || s.hole[s.o.face_of[2 * e + 1]];
      m.length[on_hole].encode(enc, length[e] - 1);
      solver.set(e, length, 0xFFFFFFFEu, true, 0);
    }
  }
  enc.finish();
  return out;
}

std::vector<TopologyCode> decode_topology(std::string_view payload, std::uint64_t base_offset,
                                          std::uint64_t component_count, std::uint64_t max_edges,
                                          std::uint64_t max_length) {
  RangeDecoder dec(payload, base_offset, "topology section");
  Models m;
  std::vector<TopologyCode> codes(component_count);
  for (TopologyCode& c : codes) {
    unsigned hi = dec.decode_bit(m.kind[0]);
    unsigned lo = dec.decode_bit(m.kind[1 + hi]);
    c.kind = static_cast<ComponentKind>(2 * hi + lo);
    if (!has_schematic(c.kind)) {
      c.a = m.size_a.decode(dec);
      c.b = m.size_b.decode(dec);
      if (c.kind == ComponentKind::kTorus) c.twist = m.twist.decode(dec);
    }
  }
  std::uint64_t edges_total = 0;
  std::vector<Traversal> trav(codes.size());
  for (std::size_t ci = 0; ci < codes.size(); ++ci) {
    TopologyCode& c = codes[ci];
    if (!has_schematic(c.kind)) continue;
    Traversal& t = trav[ci];
    auto new_edge = [&]() {
      if (++edges_total > max_edges) {
        fail(ErrorCode::kFormat,
             "topology: more schematic edges than the declared faces allow (near byte offset " +
                 std::to_string(dec.offset()) + ")");
      }
      return t.add_edge();
    };
    new_edge();
    for (std::uint32_t i = 0; i < t.labelled(); ++i) {
      std::uint32_t ctx = chain_context(t, i);
      if (dec.decode_bit(m.is_new[ctx])) {
        c.next_ref.push_back(0);
        t.link(i, new_edge());
        continue;
      }
      std::uint32_t vc = t.vend[i ^ 1u], fc = t.fend[i];
      std::uint32_t z;
      if (dec.decode_bit(m.is_vertex[ctx])) {
        z = vc;
      } else if (fc != vc && dec.decode_bit(m.is_face[ctx])) {
        z = fc;
      } else {
        std::uint32_t newest = newest_other(t, vc, fc);
        if (newest == kInvalid) {  // no third dart without predecessor: a valid stream never gets here
          fail(ErrorCode::kFormat, "topology: dart reference with no dart left to refer to" + near(dec));
        }
        if (dec.decode_bit(m.is_newest)) {
          z = newest;
        } else {
          std::int64_t r = std::int64_t{t.pool.rank(i)} + unzigzag(m.other_step.decode(dec));
          z = r >= 0 && r < t.pool.size() ? t.pool.select(static_cast<std::uint32_t>(r)) : kInvalid;
          if (z == kInvalid || z == vc || z == fc || z == newest) {
            fail(ErrorCode::kFormat,
                 "topology: dart reference out of range or not canonical (near byte offset " +
                     std::to_string(dec.offset()) + ")");
          }
        }
      }
      c.next_ref.push_back(t.pool.rank(z) + 1);
      t.link(i, z);
    }
  }
  std::vector<CornerState> cs(codes.size());
  for (std::size_t ci = 0; ci < codes.size(); ++ci) {
    if (!has_schematic(codes[ci].kind)) continue;
    CornerState& s = cs[ci];
    s.o = orbits(trav[ci].next);
    s.corner.assign(trav[ci].labelled(), 0);
    s.v_corner.assign(s.o.vertex_degree.size(), 0);
    s.v_plain.assign(s.o.vertex_degree.size(), 0);
    s.hole.assign(s.o.face_first.size(), 0);
    std::uint32_t left = m.hole_count.decode(dec);
    for (std::uint32_t f = 0; f < s.o.face_first.size() && left > 0; ++f) {
      if (s.o.face_size[f] < 4) {
        s.hole[f] = 1;
      } else {
        s.hole[f] = static_cast<std::uint8_t>(dec.decode_bit(m.is_hole[cap(s.o.face_size[f] - 4, 3)]));
      }
      left -= s.hole[f];
    }
    if (left != 0) fail(ErrorCode::kFormat, "topology: fewer faces than declared holes" + near(dec));
    for (std::uint32_t f = 0; f < s.o.face_first.size(); ++f) {
      if (!s.hole[f] && s.o.face_size[f] < 4) {
        fail(ErrorCode::kFormat, "topology: a patch with fewer than four sides" + near(dec));
      }
    }
    mark_holes(s, trav[ci].next);
  }
  for (std::size_t ci = 0; ci < codes.size(); ++ci) {
    if (!has_schematic(codes[ci].kind)) continue;
    CornerState& s = cs[ci];
    for (std::uint32_t f = 0; f < s.o.face_first.size(); ++f) {
      if (s.hole[f]) continue;
      std::uint32_t needed = 4, remaining = s.o.face_size[f];
      std::uint32_t x = s.o.face_first[f];
      do {
        bool is_corner = needed != 0 && (needed == remaining ||
                                         dec.decode_bit(m.corner[corner_context(s, x, needed, remaining)]));
        mark_corner(s, x, is_corner);
        needed -= is_corner ? 1 : 0;
        --remaining;
        x = trav[ci].next[x];
      } while (x != s.o.face_first[f]);
    }
    codes[ci].corner = s.corner;
  }
  for (std::size_t ci = 0; ci < codes.size(); ++ci) {
    TopologyCode& c = codes[ci];
    if (!has_schematic(c.kind)) continue;
    const CornerState& s = cs[ci];
    std::uint32_t edges = trav[ci].labelled() / 2;
    LengthSolver solver(s.o, s.hole, s.corner, trav[ci].next, edges);
    c.edge_length.assign(edges, 0);
    for (std::uint32_t e = 0; e < edges; ++e) {
      if (solver.known[e]) continue;
      bool on_hole = s.hole[s.o.face_of[2 * e]] || s.hole[s.o.face_of[2 * e + 1]];
      std::uint64_t len = std::uint64_t{m.length[on_hole].decode(dec)} + 1;
      if (len > max_length) {
        fail(ErrorCode::kFormat, "topology: edge length " + std::to_string(len) +
                                     " exceeds what the declared faces allow (near byte offset " +
                                     std::to_string(dec.offset()) + ")");
      }
      c.edge_length[e] = static_cast<std::uint32_t>(len);
      solver.set(e, c.edge_length, max_length, false, dec.offset());
    }
  }
  dec.finish();
  return codes;
}

}  // namespace qsp
