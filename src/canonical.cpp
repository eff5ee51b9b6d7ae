// Canonical labelling of schematic partitions (§6): colour refinement picks few candidate root darts,
// a full traversal decides among them, positions break ties left by symmetry.
#include "qsp/canonical.h"

// Header-only (XXH_INLINE_ALL): the installed library needs no xxhash to link against.
#define XXH_INLINE_ALL
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstring>
#include <exception>
#include <future>
#include <numeric>
#include <string>
#include <system_error>
#include <thread>
#include <tuple>
#include <utility>

#include "automorphisms.h"
#include "beside.h"
#include "layout_grid.h"
#include "order_set.h"
#include "qsp/error.h"
#include "u32map.h"

namespace qsp {
namespace {

[[noreturn]] void bad_code(const std::string& what) { throw Error(ErrorCode::kFormat, "topology: " + what); }

// The open labels of a traversal (darts no dart's `next` reaches yet) and how many lie below a label:
// a bit per label and an OrderSet over 64-label words, holding each word once per open label in it, so
// a step costs a few instructions on a small component and a dozen on a large one.
class OpenLabels {
 public:
  explicit OpenLabels(std::size_t n) : bits_((n + 63) / 64, 0), words_(bits_.size()) {}
  void open(std::uint32_t i) {
    bits_[i >> 6] |= bit(i);
    if (bits_.size() > 1) words_.insert(i >> 6);
  }
  void close(std::uint32_t i) {
    bits_[i >> 6] &= ~bit(i);
    if (bits_.size() > 1) words_.erase(i >> 6);
  }
  std::uint32_t below(std::uint32_t i) const {
    return words_.rank(i >> 6) + static_cast<std::uint32_t>(std::popcount(bits_[i >> 6] & (bit(i) - 1)));
  }
  void clear() {
    std::fill(bits_.begin(), bits_.end(), 0);
    words_.clear();
  }

 private:
  static std::uint64_t bit(std::uint32_t i) { return std::uint64_t{1} << (i & 63); }
  std::vector<std::uint64_t> bits_;
  OrderSet words_;
};

// What the traversals of one component share, so that trying each candidate root allocates nothing.
struct Traversal {
  explicit Traversal(std::uint32_t nd) : label(nd, kInvalid), order(nd), open(nd) {}
  std::vector<std::uint32_t> label;  // per dart: its label; all kInvalid between traversals
  std::vector<std::uint32_t> order;  // darts in label order, of the last traversal
  std::uint32_t root = kInvalid;     // the last traversal's root, if it went to the end
  OpenLabels open;                   // none open between traversals
  TopologyCode code;                 // of the last traversal (its kind is the caller's)
};

// Darts in canonical label order from `root` (into t.order), and the code of that traversal (t.code).
// The schematic is connected, so every dart gets a label and the streams are filled to their sizes.
// With `expect`, stops at the first entry that differs from it and returns false (t.code is then
// partial); true when the whole code equals it, or without `expect`.
bool traverse(const Schematic& s, std::uint32_t root, Traversal& t, const TopologyCode* expect = nullptr) {
  const std::size_t nd = t.order.size();
  // Sized only after the streams changed hands with a smaller code's (a resize call per try was a
  // seventh of trying a remembered shape's roots).
  if (t.code.next_ref.size() != nd || t.code.edge_length.size() != nd / 2 || t.code.corner.size() != nd) {
    t.code.next_ref.resize(nd);
    t.code.edge_length.resize(nd / 2);
    t.code.corner.resize(nd);
  }
  std::uint32_t* const label = t.label.data();
  std::uint32_t* const order = t.order.data();
  std::uint32_t* const next_ref = t.code.next_ref.data();
  std::uint32_t* const edge_length = t.code.edge_length.data();
  std::uint8_t* const corner = t.code.corner.data();
  std::uint32_t labelled = 0;
  bool same = true;
  t.root = kInvalid;
  auto assign = [&](std::uint32_t d) {  // labels the edge of d, d first
    label[d] = labelled;
    label[d ^ 1] = labelled + 1;
    order[labelled] = d;
    order[labelled + 1] = d ^ 1;
    t.open.open(labelled);
    t.open.open(labelled + 1);
    edge_length[labelled / 2] = s.edge_length[d >> 1];
    if (expect && expect->edge_length[labelled / 2] != edge_length[labelled / 2]) same = false;
    labelled += 2;
  };
  assign(root);
  for (std::uint32_t i = 0; i < labelled && same; ++i) {
    const std::uint32_t d = order[i], n = s.dart_next[d];
    if (label[n] == kInvalid) {
      assign(n);
      next_ref[i] = 0;
    } else {
      next_ref[i] = 1 + t.open.below(label[n]);
    }
    t.open.close(label[n]);
    corner[i] = s.dart_corner[d];
    if (expect && (expect->next_ref[i] != next_ref[i] || expect->corner[i] != corner[i])) same = false;
  }
  for (std::uint32_t i = 0; i < labelled; ++i) label[order[i]] = kInvalid;
  if (!same) {
    t.open.clear();  // stopped with darts open
    return false;
  }
  if (labelled != nd) throw Error(ErrorCode::kInternal, "canonical: schematic is not connected");
  t.root = root;
  // Every dart was opened once and closed once (next is a permutation), so none is open again.
  return true;
}

// Everything but the mesh link, numbered from the dart order alone: vertices and faces by first
// appearance, a patch's face_dart its first corner dart. The decoder uses this same function.
Schematic schematic_from_next(std::vector<std::uint32_t> next, std::vector<std::uint8_t> corner,
                              std::vector<std::uint32_t> lengths) {
  Schematic s;
  const std::uint32_t nd = static_cast<std::uint32_t>(next.size());
  s.dart_next = std::move(next);
  s.dart_corner = std::move(corner);
  s.edge_length = std::move(lengths);
  s.dart_prev.assign(nd, kInvalid);
  for (std::uint32_t d = 0; d < nd; ++d) {
    if (s.dart_next[d] >= nd || s.dart_prev[s.dart_next[d]] != kInvalid)
      bad_code("next is not a permutation");
    s.dart_prev[s.dart_next[d]] = d;
  }
  s.dart_vertex.assign(nd, kInvalid);
  s.dart_face.assign(nd, kInvalid);
  s.face_dart.reserve(nd / 4 + 1);  // most faces are patches of four or more darts
  s.face_hole.reserve(nd / 4 + 1);
  for (std::uint32_t d = 0; d < nd; ++d) {
    if (s.dart_vertex[d] == kInvalid) {
      const std::uint32_t id = s.vertex_count++;
      std::uint32_t e = d;
      do {
        s.dart_vertex[e] = id;
        e = s.dart_next[e ^ 1];
      } while (e != d);
    }
    if (s.dart_face[d] == kInvalid) {
      const std::uint32_t id = s.face_count();
      s.face_dart.push_back(kInvalid);
      std::uint32_t e = d, first_corner = kInvalid;
      do {
        s.dart_face[e] = id;
        if (s.dart_corner[e] && e < first_corner) first_corner = e;
        e = s.dart_next[e];
      } while (e != d);
      s.face_hole.push_back(first_corner == kInvalid ? 1 : 0);
      s.face_dart[id] = first_corner == kInvalid ? d : first_corner;
    }
  }
  return s;
}

int compare_codes(const TopologyCode& x, const TopologyCode& y) {
  // Lexicographic. Equal streams are the common case (tied roots, repeated components): one memcmp
  // tells, where an element-wise comparison cost a third of sorting mh_base's components.
  auto cmp = [](const auto& a, const auto& b) {
    const std::size_t n = std::min(a.size(), b.size());
    if (n != 0 && std::memcmp(a.data(), b.data(), n * sizeof a[0]) != 0) {
      const auto m = std::mismatch(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(n), b.begin());
      return *m.first <=> *m.second;
    }
    return a.size() <=> b.size();
  };
  auto t = std::make_tuple(x.kind, x.a, x.b, x.twist) <=> std::make_tuple(y.kind, y.a, y.b, y.twist);
  if (t == 0) t = x.next_ref.size() <=> y.next_ref.size();
  if (t == 0) t = cmp(x.next_ref, y.next_ref);
  if (t == 0) t = cmp(x.edge_length, y.edge_length);
  if (t == 0) t = cmp(x.corner, y.corner);
  return t < 0 ? -1 : (t > 0 ? 1 : 0);
}

// Two vertices' positions compared as float bits, x before y before z.
int compare_position(const QuadMesh& mesh, std::uint32_t a, std::uint32_t b) {
  if (a == b) return 0;
  for (int k = 0; k < 3; ++k) {
    std::uint32_t x, y;
    std::memcpy(&x, &mesh.positions[3 * std::size_t(a) + k], 4);
    std::memcpy(&y, &mesh.positions[3 * std::size_t(b) + k], 4);
    if (x != y) return x < y ? -1 : 1;
  }
  return 0;
}

// Lexicographic comparison of positions (as float bits) along two vertex sequences.
int compare_positions(const QuadMesh& mesh, const std::vector<std::uint32_t>& x,
                      const std::vector<std::uint32_t>& y) {
  const std::size_t n = std::min(x.size(), y.size());
  for (std::size_t i = 0; i < n; ++i)
    if (const int c = compare_position(mesh, x[i], y[i]); c != 0) return c;
  return x.size() < y.size() ? -1 : (x.size() > y.size() ? 1 : 0);
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
  h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
  h *= 0xFF51AFD7ED558CCDull;
  return h ^ (h >> 33);
}

// How many darts have each colour: a flat hash table sized once per component, so that counting a
// refinement round's classes costs O(darts), not a sort.
class ColourCounts {
 public:
  explicit ColourCounts(std::size_t n) {
    std::size_t cap = 16;
    while (cap < 2 * n) cap <<= 1;
    colour_.resize(cap);
    count_.resize(cap);
    shift_ = 64 - std::countr_zero(cap);
  }
  // Counts `colours`; returns how many distinct ones there are.
  std::size_t count(const std::vector<std::uint64_t>& colours) {
    std::fill(count_.begin(), count_.end(), 0);
    std::size_t distinct = 0;
    const std::size_t mask = count_.size() - 1;
    for (const std::uint64_t c : colours) {
      std::size_t i = static_cast<std::size_t>((c * 0x9E3779B97F4A7C15ull) >> shift_);
      while (count_[i] != 0 && colour_[i] != c) i = (i + 1) & mask;
      if (count_[i]++ == 0) colour_[i] = c, ++distinct;
    }
    return distinct;
  }
  // Of the last count: the colour of the fewest darts (ties: the smallest colour).
  std::uint64_t rarest() const {
    std::uint64_t best = 0;
    std::uint32_t best_count = 0;
    for (std::size_t i = 0; i < count_.size(); ++i) {
      if (count_[i] == 0) continue;
      if (best_count == 0 || count_[i] < best_count || (count_[i] == best_count && colour_[i] < best))
        best = colour_[i], best_count = count_[i];
    }
    return best;
  }

 private:
  std::vector<std::uint64_t> colour_;
  std::vector<std::uint32_t> count_;  // 0: empty slot
  int shift_ = 0;
};

// Colour refinement on darts: colours depend only on the labelled map, never on numbering. `counts`
// is left holding the returned colours' counts.
std::vector<std::uint64_t> refine(const Schematic& s, ColourCounts& counts) {
  const std::uint32_t nd = s.dart_count();
  std::vector<std::uint32_t> face_len(s.face_count(), 0), vertex_deg(s.vertex_count, 0);
  for (std::uint32_t d = 0; d < nd; ++d) {
    ++face_len[s.dart_face[d]];
    ++vertex_deg[s.dart_vertex[d]];
  }
  std::vector<std::uint64_t> c(nd), tmp(nd);
  for (std::uint32_t d = 0; d < nd; ++d) {
    std::uint64_t h = mix(s.edge_length[d >> 1], s.dart_corner[d]);
    h = mix(h, s.dart_corner[d ^ 1]);
    h = mix(h, s.face_hole[s.dart_face[d]]);
    h = mix(h, face_len[s.dart_face[d]]);
    c[d] = mix(h, vertex_deg[s.dart_vertex[d]]);
  }
  std::size_t n = counts.count(c);
  for (int round = 0; round < 64 && n < nd; ++round) {
    for (std::uint32_t d = 0; d < nd; ++d)
      tmp[d] = mix(mix(mix(c[d], c[s.dart_next[d]]), c[s.dart_prev[d]]), c[d ^ 1]);
    const std::size_t m = counts.count(tmp);
    c.swap(tmp);
    if (m == n) break;
    n = m;
  }
  return c;
}

// Candidate roots: the darts of the smallest colour class (ties: smallest colour value), increasing.
std::vector<std::uint32_t> candidate_roots(const Schematic& s) {
  const std::uint32_t nd = s.dart_count();
  ColourCounts counts(nd);
  const std::vector<std::uint64_t> colour = refine(s, counts);
  const std::uint64_t rarest = counts.rarest();
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t d = 0; d < nd; ++d)
    if (colour[d] == rarest) candidates.push_back(d);
  return candidates;
}

// Traverses from candidate roots and calls on_tie(root, fresh) for each whose code is the smallest so
// far (then in `best`, and t.order is root's traversal when fresh); fresh: smaller than every earlier one,
// which no longer tie. The roots still tied at the end are the canonical root and its images under every
// orientation-preserving automorphism (one automorphism per root: a map is fixed by one dart's image).
// A root in the orbit of the smallest code's first root under the automorphisms found so far is tied
// without a traversal.
template <class OnTie>
void smallest_codes(const Schematic& s, TopologyCode& best, Traversal& t, OnTie&& on_tie) {
  t.code.kind = best.kind;
  std::uint32_t first_tied = kInvalid;  // the smallest code's first root
  detail::Orbits orbits;
  detail::Walk walk;
  for (const std::uint32_t root : candidate_roots(s)) {
    if (orbits.same(root, first_tied)) {
      on_tie(root, false);
      continue;
    }
    traverse(s, root, t);
    const int c = first_tied == kInvalid ? -1 : compare_codes(t.code, best);
    if (c < 0) {
      std::swap(best, t.code);  // same kind and sizes: only the streams change hands
      first_tied = root;
      on_tie(root, true);
    } else if (c == 0) {
      walk.start(s, first_tied);
      orbits.add(walk, t.order);
      on_tie(root, false);
    }
  }
}

// Roots whose traversal code is the smallest (see smallest_codes), in candidate order.
std::vector<std::uint32_t> tied_roots(const Schematic& s, TopologyCode& best) {
  Traversal t(s.dart_count());
  std::vector<std::uint32_t> tied;
  smallest_codes(s, best, t, [&](std::uint32_t root, bool fresh) {
    if (fresh) tied.clear();
    tied.push_back(root);
  });
  return tied;
}

// `part` relabelled in the traversal order from `root`, still linked to the mesh.
ComponentPartition relabel(const ComponentPartition& part, std::uint32_t root, Traversal& t) {
  const Schematic& s = part.schematic;
  const std::uint32_t nd = s.dart_count();
  if (t.root != root) traverse(s, root, t);  // the last traversal tried is often the chosen one's
  const std::vector<std::uint32_t>& order = t.order;
  std::vector<std::uint32_t> label(nd);
  for (std::uint32_t i = 0; i < nd; ++i) label[order[i]] = i;
  std::vector<std::uint32_t> next(nd), lengths(nd / 2);
  std::vector<std::uint8_t> corner(nd);
  for (std::uint32_t i = 0; i < nd; ++i) {
    next[i] = label[s.dart_next[order[i]]];
    corner[i] = s.dart_corner[order[i]];
  }
  for (std::uint32_t e = 0; e < nd / 2; ++e) lengths[e] = s.edge_length[order[2 * e] >> 1];
  // Every field but the schematic, which is rebuilt: copying it only to replace it cost a tenth of
  // canonicalize.
  ComponentPartition p{
      .kind = part.kind,
      .component = part.component,
      .extraordinary = part.extraordinary,
      .schematic = schematic_from_next(std::move(next), std::move(corner), std::move(lengths)),
      .a = part.a,
      .b = part.b,
      .twist = part.twist,
      .anchor_halfedge = part.anchor_halfedge};
  p.schematic.dart_halfedge.resize(nd);
  p.schematic.vertex_mesh.assign(p.schematic.vertex_count, kInvalid);
  for (std::uint32_t i = 0; i < nd; ++i) {
    p.schematic.dart_halfedge[i] = s.dart_halfedge[order[i]];
    p.schematic.vertex_mesh[p.schematic.dart_vertex[i]] = s.vertex_mesh[s.dart_vertex[order[i]]];
  }
  return p;
}

// Chooses among the roots tied on topology (given in candidate order) by the positions their layouts
// list, the first of the smallest winning. The schematic vertices come first there and decide for most
// roots: only the roots equal to the best on them (`finalists`) are relabelled and laid out.
class RootChoice {
 public:
  RootChoice(const QuadMesh& mesh, const Schematic& s) : mesh_(mesh), s_(s) {}
  // The next tied root. `first`: the label positions where a traversal of their code first reaches each
  // schematic vertex (first_reached), the same for every root of it; `fresh`: the first root of a new
  // smallest code, the roots before no longer tied. Each root is walked only as far as it takes to
  // tell it from the best so far, and the best only as far as asked.
  void add(std::uint32_t root, bool fresh, const std::vector<std::uint32_t>& first) {
    if (fresh) {
      tied_ = 1;
      finalists_.assign(1, root);
      best_.start(s_, root);
      best_prefix_.clear();
      return;
    }
    ++tied_;
    walk_.start(s_, root);
    prefix_.clear();
    int c = 0;
    for (std::size_t j = 0; j < first.size() && c == 0; ++j) {
      prefix_.push_back(vertex(walk_, first[j]));
      if (best_prefix_.size() == j) best_prefix_.push_back(vertex(best_, first[j]));
      c = compare_position(mesh_, prefix_[j], best_prefix_[j]);
    }
    if (c < 0) {
      std::swap(best_, walk_);
      best_prefix_.swap(prefix_);
      finalists_.assign(1, root);
    } else if (c == 0) {
      finalists_.push_back(root);
    }
  }
  // The component relabelled from the chosen root, with its layout map and automorphism count.
  // `walks`: of part's patches (walk_patches), or null.
  void finish(const Adjacency& adj, const ComponentPartition& part, Traversal& t, CanonicalComponent& out,
              const PatchWalks* walks = nullptr) {
    auto map_of = [&](const ComponentPartition& p) {
      LayoutMap m;
      if (walks && link_from_walks(p, part.schematic, t.order, *walks, m)) return m;
      return layout_to_mesh(p, adj);
    };
    out.automorphisms = tied_;
    out.part = relabel(part, finalists_[0], t);
    out.map = map_of(out.part);
    for (std::size_t i = 1; i < finalists_.size(); ++i) {
      ComponentPartition p = relabel(part, finalists_[i], t);
      LayoutMap m = map_of(p);
      if (compare_positions(mesh_, m.vertex, out.map.vertex) < 0) {
        out.part = std::move(p);
        out.map = std::move(m);
      }
    }
  }

 private:
  std::uint32_t vertex(detail::Walk& w, std::uint32_t label) {
    return s_.vertex_mesh[s_.dart_vertex[w.at(label)]];
  }
  const QuadMesh& mesh_;
  const Schematic& s_;
  std::vector<std::uint32_t> finalists_;
  detail::Walk best_, walk_;  // the best root's traversal and the one being compared with it
  std::vector<std::uint32_t> best_prefix_, prefix_;  // their mesh vertices at `first`, as far as read
  std::uint32_t tied_ = 0;
};

// A small component's shape, up to isomorphism, as its canonicalization found it: a component met
// again in another place (the 125 helper cubes of a MakeHuman mesh) is canonicalized from it with
// one traversal, no colour refinement and no traversal per tied root. Its tied roots are the images
// of these, and their order is theirs by dart number, as candidate order is.
// Sums of a schematic's edge lengths and of their squares: equal for isomorphic schematics, mostly
// unequal for shapes of the same size but other proportions.
std::pair<std::uint64_t, std::uint64_t> length_sums(const std::vector<std::uint32_t>& lengths) {
  std::pair<std::uint64_t, std::uint64_t> sums{0, 0};
  for (const std::uint32_t l : lengths) sums.first += l, sums.second += std::uint64_t{l} * l;
  return sums;
}

struct KnownShape {
  TopologyCode code;  // the smallest
  std::uint32_t vertices = 0;
  std::pair<std::uint64_t, std::uint64_t> lengths;  // length_sums
  std::vector<std::uint32_t> first;   // where its traversals first reach each vertex (first_reached)
  std::vector<std::uint32_t> labels;  // per tied root, in candidate order, its label from the first
};

// Components this small are remembered (a shape costs its tied roots' and vertices' labels), this many per
// dart and vertex count (a new component tries each until one matches).
constexpr std::uint32_t kKnownShapeDarts = 256;
constexpr std::size_t kKnownShapesPerSize = 4;

struct ShapeMemory {
  std::vector<KnownShape> shapes;
};

// `part` canonicalized from a remembered shape it is isomorphic to; false (nothing done) if none is.
bool canonical_from_known(const QuadMesh& mesh, const Adjacency& adj, const ComponentPartition& part,
                          const ShapeMemory& memory, Traversal& t, CanonicalComponent& out) {
  const Schematic& s = part.schematic;
  const std::uint32_t nd = s.dart_count(), nv = s.vertex_count;
  // Tried before any root of a shape: a box met among the helper cubes once cost a dozen traversals
  // for every cube after it.
  const auto lengths = length_sums(s.edge_length);
  for (const KnownShape& k : memory.shapes) {
    if (k.code.kind != part.kind || k.code.next_ref.size() != nd || k.vertices != nv || k.lengths != lengths)
      continue;
    // A root whose first edge or corner differs fails at once: tested before a traversal is set up.
    auto matches = [&](std::uint32_t root) {
      return s.edge_length[root >> 1] == k.code.edge_length[0] && s.dart_corner[root] == k.code.corner[0] &&
             traverse(s, root, t, &k.code);
    };
    std::uint32_t root = 0;
    while (root < nd && !matches(root)) ++root;
    if (root == nd) continue;
    // t.order: the traversal from the first tied root's image. The tied roots' images, by dart.
    std::vector<std::uint32_t> roots(k.labels.size());
    for (std::size_t e = 0; e < roots.size(); ++e) roots[e] = t.order[k.labels[e]];
    std::sort(roots.begin(), roots.end());
    out.code = k.code;
    RootChoice choice(mesh, s);
    for (std::size_t r = 0; r < roots.size(); ++r) choice.add(roots[r], r == 0, k.first);
    choice.finish(adj, part, t, out);
    return true;
  }
  return false;
}

// From this many faces, a component canonicalized while the second core is idle has its patches
// walked there (link's walk, the larger part of its layout map) while this thread chooses the root.
constexpr std::uint32_t kWalksBesideFrom = 4096;

// `beside_ok`: the second core is free for this component's patch walks. `walks`: those walks, if
// another thread makes them.
CanonicalComponent canonical_general(const QuadMesh& mesh, const Adjacency& adj,
                                     const ComponentPartition& part, ShapeMemory& memory, bool beside_ok,
                                     std::shared_future<PatchWalks> walks) {
  const Schematic& s = part.schematic;
  const std::uint32_t nd = s.dart_count();
  CanonicalComponent out;
  out.code.kind = part.kind;
  Traversal t(nd);
  if (nd <= kKnownShapeDarts && canonical_from_known(mesh, adj, part, memory, t, out)) return out;
  Beside<PatchWalks> own;  // made beside here, where no other thread makes them
  if (!walks.valid() && beside_ok && adj.component_faces[part.component] >= kWalksBesideFrom)
    own = beside(true, [&part, &adj] { return walk_patches(part, adj); });
  std::size_t same_size = 0;
  for (const KnownShape& k : memory.shapes)
    same_size += k.code.next_ref.size() == nd && k.vertices == s.vertex_count;
  const bool remember = nd <= kKnownShapeDarts && same_size < kKnownShapesPerSize;
  KnownShape shape;
  shape.vertices = s.vertex_count;
  shape.lengths = length_sums(s.edge_length);
  std::vector<std::uint32_t> label_of, first;  // in the traversal from the first tied root
  std::vector<std::uint8_t> seen;
  RootChoice choice(mesh, s);
  smallest_codes(s, out.code, t, [&](std::uint32_t root, bool fresh) {
    if (fresh) {
      detail::first_reached(
          s, static_cast<std::uint32_t>(t.order.size()), [&](std::uint32_t i) { return t.order[i]; }, seen,
          first);
      if (remember) {
        label_of.resize(nd);
        for (std::uint32_t i = 0; i < nd; ++i) label_of[t.order[i]] = i;
        shape.labels.clear();
      }
    }
    choice.add(root, fresh, first);
    if (remember) shape.labels.push_back(label_of[root]);
  });
  PatchWalks own_walks;
  const PatchWalks* w = nullptr;
  if (walks.valid()) {
    w = &walks.get();
  } else if (own.valid()) {
    own_walks = own.get();
    w = &own_walks;
  }
  choice.finish(adj, part, t, out, w && w->ok ? w : nullptr);
  if (remember) {
    shape.code = out.code;
    shape.first = std::move(first);
    memory.shapes.push_back(std::move(shape));
  }
  return out;
}

// Every anchor half-edge that gives `part` (an annulus or torus) its canonical sizes, which are set in
// `base` (torus: the smallest of the lattice's forms). One anchor per orientation-preserving automorphism.
std::vector<std::uint32_t> structured_anchors(const Adjacency& adj, const ComponentPartition& part,
                                              ComponentPartition& base) {
  auto right = [&](std::uint32_t h) { return adj.next(adj.twin[adj.next(h)]); };
  auto up = [&](std::uint32_t h) { return adj.twin[adj.next(adj.next(h))]; };
  // Torus sizes from an anchor, as in partition.cpp.
  auto sizes = [&](std::uint32_t anchor, std::uint32_t faces) {
    std::uint32_t a = 0, h = anchor;
    do {
      ++a;
      h = right(h);
    } while (h != anchor);
    const std::uint32_t b = faces / a;
    h = anchor;
    for (std::uint32_t j = 0; j < b; ++j) h = up(h);
    std::uint32_t t = 0;
    for (std::uint32_t g = anchor; g != h; g = right(g)) ++t;
    return std::make_tuple(a, b, t);
  };
  std::vector<std::uint32_t> anchors;
  const std::uint32_t faces = part.a * part.b;
  base = part;
  // Work proportional to the component, not the mesh: a mesh may hold thousands of small rings.
  if (part.kind == ComponentKind::kAnnulus) {
    // Every boundary half-edge of the component: both loops, every start.
    detail::U32Map seen(faces);  // faces visited (value unused)
    seen.insert(part.anchor_halfedge >> 2, 0);
    std::vector<std::uint32_t> stack{part.anchor_halfedge >> 2};
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      for (std::uint32_t h = 4 * f; h < 4 * f + 4; ++h) {
        const std::uint32_t t = adj.twin[h];
        if (adj.is_exterior(t))
          anchors.push_back(h);
        else if (seen.insert(t >> 2, 0))
          stack.push_back(t >> 2);
      }
    }
    return anchors;
  }
  // Torus: orient every face like the anchor (its "bottom" half-edge), then try the four rotations.
  std::vector<std::uint32_t> bottom{part.anchor_halfedge};  // per face, in discovery order
  {
    detail::U32Map seen(faces);
    seen.insert(part.anchor_halfedge >> 2, 0);
    auto prev = [&](std::uint32_t h) { return adj.next(adj.next(adj.next(h))); };
    for (std::size_t i = 0; i < bottom.size(); ++i) {
      const std::uint32_t b = bottom[i];
      for (std::uint32_t g : {right(b), up(b), prev(adj.twin[prev(b)]), adj.next(adj.next(adj.twin[b]))})
        if (seen.insert(g >> 2, 0)) bottom.push_back(g);
    }
  }
  std::tuple<std::uint32_t, std::uint32_t, std::uint32_t> best{~0u, ~0u, ~0u};
  std::uint8_t good[4] = {0, 0, 0, 0};
  const std::uint32_t a0 = part.anchor_halfedge;
  for (std::uint32_t q = 0; q < 4; ++q) {
    const auto z = sizes((a0 & ~3u) | ((a0 + q) & 3u), faces);
    if (z < best) {
      best = z;
      std::fill(good, good + 4, 0);
    }
    if (z == best) good[q] = 1;
  }
  std::tie(base.a, base.b, base.twist) = best;
  for (std::uint32_t b : bottom)
    for (std::uint32_t q = 0; q < 4; ++q)
      if (good[q]) anchors.push_back((b & ~3u) | ((b + q) & 3u));
  return anchors;
}

// `base` (from structured_anchors) anchored at `h`.
ComponentPartition at_anchor(const Adjacency& adj, const ComponentPartition& base, std::uint32_t h) {
  ComponentPartition p = base;
  p.anchor_halfedge = h;
  if (p.kind == ComponentKind::kAnnulus) {
    // a = this loop's length (equal for both loops of a structured annulus).
    const std::uint32_t faces = base.a * base.b;
    std::uint32_t a = 0, g = h;
    do {
      ++a;
      g = adj.next(adj.twin[adj.next(g)]);
    } while (g != h);
    p.a = a;
    p.b = faces / a;
  }
  return p;
}

// Annulus and torus: sizes are fixed by topology (torus: the smallest of the lattice's forms);
// the anchor is chosen by positions among all anchors giving those sizes.
CanonicalComponent canonical_structured(const QuadMesh& mesh, const Adjacency& adj,
                                        const ComponentPartition& part) {
  ComponentPartition base;
  const std::vector<std::uint32_t> anchors = structured_anchors(adj, part, base);
  // Smallest first position, then full comparison among those.
  CanonicalComponent out;
  out.code.kind = part.kind;
  std::uint32_t best_anchor = kInvalid;
  std::uint32_t ties = 0;
  std::vector<std::uint32_t> first;
  for (std::uint32_t h : anchors) {
    const int c = first.empty() ? -1 : compare_position(mesh, adj.origin[h], adj.origin[first[0]]);
    if (c < 0)
      first.assign(1, h);
    else if (c == 0)
      first.push_back(h);
  }
  for (std::uint32_t h : first) {
    ComponentPartition p = at_anchor(adj, base, h);
    LayoutMap m = layout_to_mesh(p, adj);
    const int c = best_anchor == kInvalid ? -1 : compare_positions(mesh, m.vertex, out.map.vertex);
    if (c < 0) {
      best_anchor = h;
      out.part = std::move(p);
      out.map = std::move(m);
      ties = 1;
    } else if (c == 0) {
      ++ties;
    }
  }
  out.code.a = out.part.a;
  out.code.b = out.part.b;
  out.code.twist = out.part.kind == ComponentKind::kTorus ? out.part.twist : 0;
  out.automorphisms = ties;
  return out;
}

}  // namespace

bool operator==(const TopologyCode& x, const TopologyCode& y) { return compare_codes(x, y) == 0; }
bool operator<(const TopologyCode& x, const TopologyCode& y) { return compare_codes(x, y) < 0; }

namespace {

bool is_general(const ComponentPartition& part) {
  return part.kind == ComponentKind::kUnstructured || part.kind == ComponentKind::kDisk;
}

// `beside_ok`, `walks`: as canonical_general's.
CanonicalComponent canonical_component(const QuadMesh& mesh, const Adjacency& adj,
                                       const ComponentPartition& part, ShapeMemory& memory, bool beside_ok,
                                       std::shared_future<PatchWalks> walks = {}) {
  if (!is_general(part)) return canonical_structured(mesh, adj, part);
  return canonical_general(mesh, adj, part, memory, beside_ok, std::move(walks));
}

// A component's share of the work, roughly: its layout's faces, and its darts times the traversals of
// the colour refinement and the candidate roots.
std::uint64_t canonical_cost(const Adjacency& adj, const ComponentPartition& part) {
  return std::uint64_t{adj.component_faces[part.component]} + 16 * std::uint64_t{part.schematic.dart_count()};
}

// From this much work on other components than the largest, a second thread pays for its start.
constexpr std::uint64_t kSecondThreadFrom = 4096;

// The components canonicalized on two threads, each taking the next component (largest first) as it
// finishes one. Each component's result depends on that component alone, so it is the same whichever
// thread computes it. An error is the one the first failing component (in partition order) gives, as
// on one thread.
void canonical_components_on_two_threads(const QuadMesh& mesh, const Adjacency& adj,
                                         const Partition& partition, std::vector<CanonicalComponent>& out) {
  const std::size_t n = partition.components.size();
  std::vector<std::uint64_t> cost(n);
  for (std::size_t i = 0; i < n; ++i) cost[i] = canonical_cost(adj, partition.components[i]);
  std::vector<std::uint32_t> work(n);
  std::iota(work.begin(), work.end(), 0);
  std::stable_sort(work.begin(), work.end(),
                   [&](std::uint32_t x, std::uint32_t y) { return cost[x] > cost[y]; });
  std::vector<std::exception_ptr> failed(n);
  std::atomic<std::size_t> next{0};
  // A large first component has its patches walked by the helper before it takes components: that
  // one's root is chosen meanwhile, and the others, done sooner, left the helper idle at the end.
  const ComponentPartition& largest = partition.components[work[0]];
  const bool walk_largest = is_general(largest) && adj.component_faces[largest.component] >= kWalksBesideFrom;
  std::promise<PatchWalks> walked;
  std::shared_future<PatchWalks> walks;
  if (walk_largest) walks = walked.get_future().share();
  auto run = [&](bool walk_first) {
    if (walk_first) walked.set_value(walk_patches(largest, adj));
    ShapeMemory memory;  // each thread its own: a component's result never depends on it
    for (std::size_t k; (k = next.fetch_add(1, std::memory_order_relaxed)) < n;) {
      const std::uint32_t i = work[k];
      try {
        out[i] = canonical_component(mesh, adj, partition.components[i], memory, false,
                                     k == 0 ? walks : std::shared_future<PatchWalks>{});
      } catch (...) {
        failed[i] = std::current_exception();
      }
    }
  };
  Helper helper;
  try {
    helper = start_beside([&run, walk_largest] { run(walk_largest); });
  } catch (const std::system_error&) {
    walks = {};  // no thread to be had: this one does all, and walks nothing beside
  }
  run(false);
  if (helper.joinable()) helper.join();
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
}

}  // namespace

CanonicalMesh canonicalize(const QuadMesh& mesh, const Adjacency& adj, const Partition& partition,
                           unsigned threads) {
  CanonicalMesh out;
  const std::size_t n = partition.components.size();
  bool two = false;
  if (n >= 2 && threads != 1 && threads_allowed()) {
    std::uint64_t total = 0, largest = 0;
    for (const auto& part : partition.components) {
      const std::uint64_t c = canonical_cost(adj, part);
      total += c;
      largest = std::max(largest, c);
    }
    two = threads >= 2 || total - largest >= kSecondThreadFrom;
  }
  if (two) {
    out.components.resize(n);
    canonical_components_on_two_threads(mesh, adj, partition, out.components);
  } else {
    out.components.reserve(n);
    ShapeMemory memory;
    // The second core idle: a large component's patches are walked there.
    const bool beside_ok = threads != 1 && threads_allowed();
    for (const auto& part : partition.components)
      out.components.push_back(canonical_component(mesh, adj, part, memory, beside_ok));
  }
  std::vector<std::uint32_t> idx(out.components.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::uint32_t x, std::uint32_t y) {
    const int c = compare_codes(out.components[x].code, out.components[y].code);
    if (c != 0) return c < 0;
    const int p = compare_positions(mesh, out.components[x].map.vertex, out.components[y].map.vertex);
    return p != 0 ? p < 0 : x < y;
  });
  std::vector<CanonicalComponent> sorted;
  sorted.reserve(idx.size());
  for (std::uint32_t i : idx) sorted.push_back(std::move(out.components[i]));
  out.components = std::move(sorted);
  // Vertices in no face have no structure to order them by: their positions (as float bits) do, so a
  // renumbered copy gives the same file. Equal positions are interchangeable.
  out.unreferenced = partition.unreferenced;
  auto bits = [&](std::uint32_t v) {
    std::array<std::uint32_t, 3> b{};
    if (3 * std::size_t{v} + 2 < mesh.positions.size())
      std::memcpy(b.data(), &mesh.positions[3 * std::size_t{v}], 12);
    return b;
  };
  std::stable_sort(out.unreferenced.begin(), out.unreferenced.end(),
                   [&](std::uint32_t x, std::uint32_t y) { return bits(x) < bits(y); });
  return out;
}

std::vector<std::uint32_t> canonical_starts(const Adjacency& adj, const CanonicalComponent& comp) {
  if (comp.part.kind == ComponentKind::kAnnulus || comp.part.kind == ComponentKind::kTorus) {
    ComponentPartition base;
    return structured_anchors(adj, comp.part, base);
  }
  TopologyCode best;
  best.kind = comp.code.kind;
  return tied_roots(comp.part.schematic, best);
}

ComponentPartition canonical_from_start(const Adjacency& adj, const CanonicalComponent& comp,
                                        std::uint32_t start) {
  if (comp.part.kind == ComponentKind::kAnnulus || comp.part.kind == ComponentKind::kTorus)
    return at_anchor(adj, comp.part, start);
  Traversal t(comp.part.schematic.dart_count());
  return relabel(comp.part, start, t);
}

ComponentPartition partition_from_code(const TopologyCode& code) {
  ComponentPartition p;
  p.kind = code.kind;
  if (code.kind == ComponentKind::kAnnulus || code.kind == ComponentKind::kTorus) {
    if (!code.next_ref.empty() || !code.edge_length.empty() || !code.corner.empty())
      bad_code("structured component carries schematic streams");
    p.a = code.a;
    p.b = code.b;
    p.twist = code.twist;
    const std::string why = validate(p);
    if (!why.empty()) bad_code(why);
    if (static_cast<std::uint64_t>(p.a) * (p.b + 1) > 0xFFFFFFF0u) bad_code("structured component too large");
    return p;
  }
  if (code.kind != ComponentKind::kUnstructured && code.kind != ComponentKind::kDisk)
    bad_code("unknown component kind");
  const std::size_t nd = code.next_ref.size();
  if (nd < 2 || nd % 2 || code.corner.size() != nd || code.edge_length.size() * 2 != nd)
    bad_code("stream sizes disagree");
  std::vector<std::uint32_t> next(nd, kInvalid);
  OrderSet open(nd);
  std::size_t labelled = 2, open_count = 2;
  open.insert(0);
  open.insert(1);
  for (std::size_t i = 0; i < nd; ++i) {
    if (i >= labelled) bad_code("traversal ends before its streams do");
    const std::uint32_t ref = code.next_ref[i];
    std::size_t target;
    if (ref == 0) {
      if (labelled + 2 > nd) bad_code("more edges than declared");
      target = labelled;
      open.insert(labelled);
      open.insert(labelled + 1);
      labelled += 2;
      open_count += 2;
    } else {
      if (ref > open_count) bad_code("reference to a dart that is not open");
      target = open.select(ref - 1);
    }
    open.erase(target);
    --open_count;
    next[i] = static_cast<std::uint32_t>(target);
  }
  if (labelled != nd || open_count != 0) bad_code("traversal does not close");
  p.schematic = schematic_from_next(std::move(next), code.corner, code.edge_length);
  const std::string why = validate(p);
  if (!why.empty()) bad_code(why);
  return p;
}

std::uint64_t topology_fingerprint(const CanonicalMesh& mesh) {
  XXH3_state_t* st = XXH3_createState();
  XXH3_64bits_reset(st);
  auto put = [&](const void* p, std::size_t n) { XXH3_64bits_update(st, p, n); };
  const std::uint64_t head[2] = {mesh.components.size(), mesh.unreferenced.size()};
  put(head, sizeof head);
  for (const auto& c : mesh.components) {
    const std::uint32_t h[5] = {static_cast<std::uint32_t>(c.code.kind), c.code.a, c.code.b, c.code.twist,
                                static_cast<std::uint32_t>(c.code.next_ref.size())};
    put(h, sizeof h);
    put(c.code.next_ref.data(), c.code.next_ref.size() * 4);
    put(c.code.edge_length.data(), c.code.edge_length.size() * 4);
    put(c.code.corner.data(), c.code.corner.size());
  }
  const std::uint64_t out = XXH3_64bits_digest(st);
  XXH3_freeState(st);
  return out;
}

}  // namespace qsp
