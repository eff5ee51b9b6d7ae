// Cutting each component along its motorcycle graph into patches, and the schematic partition (§4).
#include "qsp/partition.h"

#include <algorithm>
#include <array>
#include <bit>
#include <future>
#include <span>
#include <string>

#include "beside.h"
#include "face_sets.h"
#include "qsp/error.h"

namespace qsp {
namespace {

[[noreturn]] void internal(const std::string& what) {
  throw Error(ErrorCode::kInternal, "partition: " + what + " (please report this mesh)");
}

// Straight ahead through the valence-4 vertex at h's head, and one row up, in grid terms:
// for the bottom half-edge h of cell (i,j), right(h) is the bottom of (i+1,j), up(h) of (i,j+1).
std::uint32_t right_of(const Adjacency& adj, std::uint32_t h) { return adj.next(adj.twin[adj.next(h)]); }
std::uint32_t up_of(const Adjacency& adj, std::uint32_t h) { return adj.twin[adj.next(adj.next(h))]; }

// Structured annulus or torus component: find sizes from an anchor half-edge.
void structured_closed(const Adjacency& adj, ComponentPartition& part, std::uint32_t anchor,
                       std::uint32_t faces) {
  part.anchor_halfedge = anchor;
  std::uint32_t a = 0, h = anchor;
  do {
    ++a;
    h = right_of(adj, h);
    if (a > faces) internal("structured component row does not close");
  } while (h != anchor);
  if (faces % a != 0) internal("structured component is not a whole number of rows");
  part.a = a;
  part.b = faces / a;
  if (part.kind == ComponentKind::kTorus) {
    h = anchor;
    for (std::uint32_t j = 0; j < part.b; ++j) h = up_of(adj, h);
    std::uint32_t t = 0, g = anchor;
    while (g != h) {
      g = right_of(adj, g);
      if (++t >= a) internal("torus rows do not line up");
    }
    part.twist = t;
  }
}

}  // namespace

const char* component_kind_name(ComponentKind kind) noexcept {
  switch (kind) {
    case ComponentKind::kUnstructured:
      return "unstructured";
    case ComponentKind::kDisk:
      return "disk";
    case ComponentKind::kAnnulus:
      return "annulus";
    case ComponentKind::kTorus:
      return "torus";
  }
  return "?";
}

std::uint32_t Schematic::patch_count() const {
  return static_cast<std::uint32_t>(std::count(face_hole.begin(), face_hole.end(), 0));
}

PatchSize patch_size(const Schematic& s, std::uint32_t face) {
  PatchSize size;
  std::uint32_t side = 0, d = s.face_dart[face];
  do {
    if (side == 0) size.a += s.edge_length[d >> 1];
    if (side == 1) size.b += s.edge_length[d >> 1];
    d = s.dart_next[d];
    if (s.dart_corner[d]) ++side;
  } while (d != s.face_dart[face] && side < 2);
  return size;
}

Partition partition_motorcycle(const Adjacency& adj) {
  return partition_from_cuts(adj, trace_motorcycles(adj, extraordinary_vertices(adj)).traced);
}

Partition partition_from_cuts(const Adjacency& adj, std::span<const std::uint32_t> cuts, bool tiling) {
  Partition out;
  const std::uint32_t nh = adj.halfedge_count(), nf = adj.face_count;

  // cut: the half-edge lies on a track or on the boundary. A bit per half-edge: the cut ones, a few
  // in a hundred on a big mesh, are then found word by word instead of by a test per half-edge.
  const std::size_t words = (std::size_t{nh} + 63) / 64;
  auto bit = [](std::uint32_t h) { return std::uint64_t{1} << (h & 63); };
  auto has = [&](const std::vector<std::uint64_t>& set, std::uint32_t h) {
    return (set[h >> 6] & bit(h)) != 0;
  };
  std::vector<std::uint64_t> cut(words, 0);
  auto set_cut = [&](std::uint32_t h) {
    cut[h >> 6] |= bit(h);
    cut[adj.twin[h] >> 6] |= bit(adj.twin[h]);
  };
  for (std::uint32_t h = 4 * nf; h < nh; ++h) set_cut(h);
  for (std::uint32_t h : cuts) {
    if (h >= nh) internal("cut half-edge out of range");
    set_cut(h);
  }

  // Regions: faces connected across uncut edges, for the checks that a patch has one boundary loop
  // and that every region is a patch. Without `tiling` they are left out with it: layouts that map
  // one-to-one onto every face (the caller's check) leave no region out and use none twice. (The
  // labelling cost 2M of mh_base's 105M instructions on the main thread.)
  std::vector<std::uint32_t> region_first_face, region;
  if (tiling)
    region = detail::label_face_sets(
        nf, adj.twin, [&](std::uint32_t h) { return !has(cut, h); }, region_first_face);

  // Per component: counts that decide its kind.
  const std::uint32_t nc = adj.component_count;
  std::vector<std::uint32_t> comp_x(nc, 0), comp_boundary(nc, 0), comp_corners(nc, 0);
  auto comp_of_vertex = [&](std::uint32_t v) {
    const std::uint32_t h = adj.vertex_halfedge[v];
    return adj.face_component[adj.is_exterior(h) ? adj.face(adj.twin[h]) : adj.face(h)];
  };
  // Schematic vertices X: nonzero deficiency in the mesh, or a corner of some patch (added below).
  std::vector<std::uint8_t> is_x(adj.vertex_count, 0);
  for (std::uint32_t v = 0; v < adj.vertex_count; ++v) {
    if (adj.valence[v] == 0) {
      out.unreferenced.push_back(v);
      continue;
    }
    if (adj.deficiency(v) != 0) is_x[v] = 1;
    if (adj.extraordinary(v)) ++comp_x[comp_of_vertex(v)];
  }
  for (std::uint32_t h = 4 * nf; h < nh; ++h) {
    const std::uint32_t c = adj.face_component[adj.face(adj.twin[h])];
    ++comp_boundary[c];
    if (adj.valence[adj.origin[h]] == 2) ++comp_corners[c];
  }

  out.components.resize(nc);
  std::uint32_t unanchored = 0;  // tori and annuli
  for (std::uint32_t c = 0; c < nc; ++c) {
    out.components[c].component = c;
    out.components[c].extraordinary = comp_x[c];
    if (comp_x[c] == 0 && comp_corners[c] == 0) {
      // Structured without corners: torus (closed) or annulus (Lemma 2). Anchor: first face's first
      // half-edge for a torus; for an annulus a boundary half-edge, found below.
      out.components[c].kind = comp_boundary[c] == 0 ? ComponentKind::kTorus : ComponentKind::kAnnulus;
      ++unanchored;
    } else if (comp_x[c] == 0) {
      if (comp_corners[c] != 4)
        internal("structured component with " + std::to_string(comp_corners[c]) + " corners");
      out.components[c].kind = ComponentKind::kDisk;
    }
  }
  if (unanchored != 0) {  // (most meshes have neither)
    std::vector<std::uint32_t> comp_faces(nc, 0);
    for (std::uint32_t f = 0; f < nf; ++f) ++comp_faces[adj.face_component[f]];
    std::vector<std::uint8_t> anchored(nc, 0);
    auto anchor = [&](std::uint32_t c, std::uint32_t h) {
      anchored[c] = 1;
      --unanchored;
      structured_closed(adj, out.components[c], h, comp_faces[c]);
    };
    // An annulus: its first interior half-edge on the boundary, the twin of its first exterior one
    // (build_adjacency numbers them in the order of their twins), not found by a scan of the faces.
    for (std::uint32_t x = 4 * nf; x < nh && unanchored != 0; ++x) {
      const std::uint32_t h = adj.twin[x], c = adj.face_component[h >> 2];
      if (!anchored[c] && out.components[c].kind == ComponentKind::kAnnulus) anchor(c, h);
    }
    for (std::uint32_t f = 0; f < nf && unanchored != 0; ++f) {
      const std::uint32_t c = adj.face_component[f];
      if (!anchored[c] && out.components[c].kind == ComponentKind::kTorus) anchor(c, 4 * f);
    }
  }

  // corner_here (a bit per half-edge): origin(h) is a corner of the region on h's left (h a cut
  // interior half-edge).
  auto general = [&](std::uint32_t c) {
    const auto k = out.components[c].kind;
    return k == ComponentKind::kUnstructured || k == ComponentKind::kDisk;
  };
  std::vector<std::uint64_t> corner_here(words, 0);
  // Cut half-edges in increasing order (`listed`, a bit each), with the cut half-edge after each
  // around the face or region on its left. A listed half-edge's index is the listed ones before it:
  // counted per byte, then within its byte (a hash map of them cost 1.2M of mh_base's instructions,
  // a binary search 2M of mh_female_generic's 160M).
  //
  // From 4096 faces this and the runs below are found in two halves, the second on another thread
  // (idle here), each half in its own lists, joined in order; errors come as on one thread, the
  // first half's first (mh_base: 1M of the main thread's instructions).
  const bool halves = nf >= 4096;
  std::vector<std::uint64_t> listed(words, 0);
  struct Cuts {
    std::vector<std::uint32_t> list, next, corner;  // corner: the g of corner_here, set after the join
  };
  // The cut half-edges in words [w0, w1) of `cut`; writes only those words of `listed`.
  auto list_cuts = [&](std::size_t w0, std::size_t w1, Cuts& out_cuts) {
    // At most the boundary's two sides and the cuts': growing them cost mh_base 0.3M instructions.
    const std::size_t most = 2 * (std::size_t{nh} - 4 * nf + cuts.size());
    out_cuts.list.reserve(most);
    out_cuts.next.reserve(most);
    auto list = [&](std::uint32_t h, std::uint32_t next) {
      listed[h >> 6] |= bit(h);
      out_cuts.list.push_back(h);
      out_cuts.next.push_back(next);
    };
    for (std::size_t w = w0; w < w1; ++w)
      for (std::uint64_t rest = cut[w]; rest != 0; rest &= rest - 1) {
        const auto h = static_cast<std::uint32_t>(64 * w + static_cast<unsigned>(std::countr_zero(rest)));
        if (adj.is_exterior(h)) {
          list(h, adj.next(h));
          continue;
        }
        if (!general(adj.face_component[h >> 2])) continue;
        std::uint32_t g = adj.next(h), faces = 1;
        while (!has(cut, g)) {
          g = adj.next(adj.twin[g]);
          if (++faces > adj.valence[adj.origin[g]]) internal("region boundary walk does not close");
        }
        list(h, g);
        if (faces == 1) {
          out_cuts.corner.push_back(g);
        } else if (faces > 2) {
          internal("vertex " + std::to_string(adj.origin[g]) + " has negative deficiency in its patch");
        }
      }
  };
  Cuts first_cuts, second_cuts;
  {
    const std::size_t mid_word = halves ? words / 2 : words;
    auto second = beside(halves, [&, mid_word] { list_cuts(mid_word, words, second_cuts); });
    list_cuts(0, mid_word, first_cuts);
    second.get();
  }
  std::vector<std::uint32_t>& cut_list = first_cuts.list;
  std::vector<std::uint32_t>& cut_next = first_cuts.next;
  cut_list.insert(cut_list.end(), second_cuts.list.begin(), second_cuts.list.end());
  cut_next.insert(cut_next.end(), second_cuts.next.begin(), second_cuts.next.end());
  for (const Cuts* c : {&first_cuts, &second_cuts})
    for (std::uint32_t g : c->corner) {
      corner_here[g >> 6] |= bit(g);
      is_x[adj.origin[g]] = 1;
    }
  // Bytes, not words, and a table: without -mpopcnt std::popcount is a library call (0.65M of
  // mh_base's instructions).
  static constexpr auto kOnes = [] {
    std::array<std::uint8_t, 256> t{};
    for (unsigned b = 1; b < 256; ++b) t[b] = static_cast<std::uint8_t>(t[b >> 1] + (b & 1));
    return t;
  }();
  auto listed_byte = [&](std::size_t i) {
    return static_cast<unsigned>(listed[i >> 3] >> (8 * (i & 7))) & 255;
  };
  std::vector<std::uint32_t> listed_before(8 * words + 1, 0);
  for (std::size_t i = 0; i < 8 * words; ++i) listed_before[i + 1] = listed_before[i] + kOnes[listed_byte(i)];
  auto cut_index = [&](std::uint32_t h) -> std::uint32_t {
    if (!has(listed, h)) return kInvalid;
    return listed_before[h >> 3] + kOnes[listed_byte(h >> 3) & ((1u << (h & 7)) - 1)];
  };
  auto next_cut = [&](std::uint32_t h) {
    const std::uint32_t i = cut_index(h);
    if (i == kInvalid) internal("cut path leaves the cut edges");
    return cut_next[i];
  };

  // Darts: maximal runs of cut half-edges between X vertices along each face/region loop.
  std::vector<std::uint32_t> run_at(cut_list.size(), kInvalid);  // by cut index: run starting there
  auto dart_at = [&](std::uint32_t h) {
    const std::uint32_t i = cut_index(h);
    return i == kInvalid ? kInvalid : run_at[i];
  };
  struct Run {
    std::uint32_t first, last, length, comp;
  };
  // The runs from cut indices [i0, i1), numbered from 0 in `run_at`.
  auto find_runs = [&](std::uint32_t i0, std::uint32_t i1, std::vector<Run>& found) {
    found.reserve(i1 - i0);
    for (std::uint32_t i = i0; i < i1; ++i) {
      const std::uint32_t h = cut_list[i];
      if (!is_x[adj.origin[h]]) continue;
      const std::uint32_t comp = adj.face_component[adj.is_exterior(h) ? adj.face(adj.twin[h]) : adj.face(h)];
      if (!general(comp)) continue;
      std::uint32_t g = h, len = 1;
      while (!is_x[adj.dest(g)]) {
        g = next_cut(g);
        if (++len > nh) internal("schematic edge does not end");
      }
      run_at[i] = static_cast<std::uint32_t>(found.size());
      found.push_back({h, g, len, comp});
    }
  };
  std::vector<Run> runs, second_runs;
  {
    const auto n = static_cast<std::uint32_t>(cut_list.size()), mid_cut = halves ? n / 2 : n;
    auto second = beside(halves, [&, n, mid_cut] { find_runs(mid_cut, n, second_runs); });
    find_runs(0, mid_cut, runs);
    second.get();
    const auto before = static_cast<std::uint32_t>(runs.size());
    for (std::uint32_t i = mid_cut; i < n; ++i)
      if (run_at[i] != kInvalid) run_at[i] += before;
    runs.insert(runs.end(), second_runs.begin(), second_runs.end());
  }
  // Group runs by component (counting sort: comp_runs[comp_run_start[c]...] are c's, increasing) and
  // number them per component: twins become darts 2e, 2e+1.
  std::vector<std::uint32_t> comp_run_start(nc + 1, 0), comp_runs(runs.size());
  for (const Run& r : runs) ++comp_run_start[r.comp + 1];
  for (std::uint32_t c = 0; c < nc; ++c) comp_run_start[c + 1] += comp_run_start[c];
  {
    std::vector<std::uint32_t> fill(comp_run_start.begin(), comp_run_start.end() - 1);
    for (std::uint32_t r = 0; r < runs.size(); ++r) comp_runs[fill[runs[r].comp]++] = r;
  }
  auto runs_of = [&](std::uint32_t c) {
    return std::span<const std::uint32_t>(comp_runs.data() + comp_run_start[c],
                                          comp_runs.data() + comp_run_start[c + 1]);
  };
  std::vector<std::uint32_t> run_dart(runs.size(), kInvalid);
  std::vector<std::uint32_t> local_region(region_first_face.size(), kInvalid);
  // The schematics of components [c0, c1); each writes only its own runs' darts and regions.
  auto build_schematics = [&](std::uint32_t c0, std::uint32_t c1) {
    for (std::uint32_t c = c0; c < c1; ++c) {
      auto& part = out.components[c];
      if (!general(c)) continue;
      Schematic& s = part.schematic;
      std::uint32_t nd = 0;
      for (std::uint32_t r : runs_of(c)) {
        if (run_dart[r] != kInvalid) continue;
        const std::uint32_t t = dart_at(adj.twin[runs[r].last]);
        if (t == kInvalid || runs[t].length != runs[r].length || adj.twin[runs[t].last] != runs[r].first)
          internal("the two sides of a schematic edge disagree");
        if (t == r) internal("schematic edge is its own twin");
        run_dart[r] = nd++;
        run_dart[t] = nd++;
        s.edge_length.push_back(runs[r].length);
      }
      s.dart_vertex.assign(nd, kInvalid);
      s.dart_next.assign(nd, kInvalid);
      s.dart_prev.assign(nd, kInvalid);
      s.dart_face.assign(nd, kInvalid);
      s.dart_corner.assign(nd, 0);
      s.dart_halfedge.assign(nd, kInvalid);
      // Vertices numbered by first appearance; faces: regions and holes by first dart.
      for (std::uint32_t r : runs_of(c)) {
        const std::uint32_t d = run_dart[r];
        s.dart_halfedge[d] = runs[r].first;
        s.dart_corner[d] = has(corner_here, runs[r].first) ? 1 : 0;
        const std::uint32_t nxt = dart_at(next_cut(runs[r].last));
        if (nxt == kInvalid) internal("schematic face boundary breaks");
        s.dart_next[d] = run_dart[nxt];
        s.dart_prev[run_dart[nxt]] = d;
      }
      // Vertex ids.
      {
        for (std::uint32_t d = 0; d < nd; ++d) {
          if (s.dart_vertex[d] != kInvalid) continue;
          const std::uint32_t id = s.vertex_count++;
          s.vertex_mesh.push_back(adj.origin[s.dart_halfedge[d]]);
          // Darts leaving the same vertex: rotate d -> next(twin(d)) (clockwise around the vertex).
          std::uint32_t e = d, guard = 0;
          do {
            s.dart_vertex[e] = id;
            e = s.dart_next[e ^ 1];
            if (++guard > nd) internal("schematic vertex rotation does not close");
          } while (e != d);
        }
      }
      // Face ids: regions keep one id per region; each hole loop is its own face.
      std::vector<std::uint32_t> used_regions;
      for (std::uint32_t d = 0; d < nd; ++d) {
        if (s.dart_face[d] != kInvalid) continue;
        const std::uint32_t h = s.dart_halfedge[d];
        const std::uint32_t id = s.face_count();
        const bool hole = adj.is_exterior(h);
        if (!hole && tiling) {
          const std::uint32_t r = region[h >> 2];
          if (local_region[r] != kInvalid)
            internal("patch has more than one boundary loop (an annulus inside an unstructured component)");
          local_region[r] = id;
          used_regions.push_back(r);
        }
        s.face_hole.push_back(hole ? 1 : 0);
        s.face_dart.push_back(kInvalid);
        std::uint32_t e = d, corners = 0, guard = 0;
        do {
          s.dart_face[e] = id;
          if (s.dart_corner[e]) {
            ++corners;
            if (s.face_dart[id] == kInvalid) s.face_dart[id] = e;
          }
          e = s.dart_next[e];
          if (++guard > nd) internal("schematic face does not close");
        } while (e != d);
        if (hole) {
          s.face_dart[id] = d;
        } else if (corners != 4) {
          internal("patch with " + std::to_string(corners) + " corners");
        }
      }
      for (std::uint32_t r : used_regions) local_region[r] = kInvalid;
    }
  };
  // From 4096 faces, the components from `mid` on (about half the runs) are built and validated on
  // a second thread, idle here (mh_base: 1.7M of the main thread's instructions). Their errors come
  // after the first half's, as on one thread; with `tiling` all is on this one.
  std::uint32_t mid = nc;
  if (!tiling && nf >= 4096 && runs.size() >= 256)
    mid = static_cast<std::uint32_t>(
        std::lower_bound(comp_run_start.begin(), comp_run_start.end() - 1, comp_run_start[nc] / 2) -
        comp_run_start.begin());
  auto rest = beside(mid < nc, [&, mid] {
    build_schematics(mid, nc);
    std::vector<std::string> why;
    for (std::uint32_t c = mid; c < nc; ++c) why.push_back(validate(out.components[c]));
    return why;
  });
  build_schematics(0, mid);
  const std::vector<std::string> rest_why = rest.get();
  // Every face must belong to a patch that made it into a schematic (regions without any X vertex on
  // their boundary inside an unstructured component would be lost otherwise).
  if (tiling) {
    std::vector<std::uint8_t> seen(region_first_face.size(), 0);
    for (const auto& part : out.components)
      for (std::uint32_t d = 0; d < part.schematic.dart_count(); ++d) {
        const std::uint32_t h = part.schematic.dart_halfedge[d];
        if (!adj.is_exterior(h)) seen[region[h >> 2]] = 1;
      }
    for (std::uint32_t r = 0; r < seen.size(); ++r)
      if (!seen[r] && general(adj.face_component[region_first_face[r]]))
        internal("a patch has no schematic vertex on its boundary (face " +
                 std::to_string(region_first_face[r]) + ")");
  }
  // Never hand out a wrong partition: every patch must be a grid and the patches must tile.
  std::vector<std::uint8_t> face_seen, vertex_seen;
  for (const auto& part : out.components) {
    if (part.component >= mid) {
      if (!rest_why[part.component - mid].empty())
        internal("component " + std::to_string(part.component) + ": " + rest_why[part.component - mid]);
      continue;
    }
    std::string why = validate(part);
    if (why.empty() && tiling)
      why = check_tiling(part, adj, layout_to_mesh(part, adj), face_seen, vertex_seen);
    if (!why.empty()) internal("component " + std::to_string(part.component) + ": " + why);
  }
  return out;
}

}  // namespace qsp
