// A partition on its mesh (PatchView), the stored partition of a .qsp rebuilt on its decoded mesh, and
// the layout and patch exports as OBJ/PLY text.
#include "qsp/layout_export.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <span>
#include <string>
#include <utility>

#include "qsp/error.h"

namespace qsp {
namespace {

bool structured_closed(const ComponentPartition& part) {
  return part.kind == ComponentKind::kAnnulus || part.kind == ComponentKind::kTorus;
}

void append_float(std::string& out, float x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, r.ptr);
}

void append_uint(std::string& out, std::uint64_t x) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, r.ptr);
}

void append_vertex(std::string& out, std::span<const float> positions, std::uint32_t v) {
  out += "v ";
  append_float(out, positions[3 * std::size_t{v}]);
  out += ' ';
  append_float(out, positions[3 * std::size_t{v} + 1]);
  out += ' ';
  append_float(out, positions[3 * std::size_t{v} + 2]);
  out += '\n';
}

// Greedy colouring in patch order: the first class, from a start that moves with the patch number
// (so the picture is not mostly class 0), that no coloured neighbour has; else the least used one.
std::vector<std::uint32_t> colour_patches(std::uint32_t patches,
                                          const std::vector<std::pair<std::uint32_t, std::uint32_t>>& touch) {
  std::vector<std::uint32_t> first(patches + 1, 0), nbr(2 * touch.size());
  for (const auto& [p, q] : touch) ++first[p + 1], ++first[q + 1];
  for (std::uint32_t p = 0; p < patches; ++p) first[p + 1] += first[p];
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (const auto& [p, q] : touch) nbr[fill[p]++] = q, nbr[fill[q]++] = p;
  }
  std::vector<std::uint32_t> colour(patches, kInvalid);
  for (std::uint32_t p = 0; p < patches; ++p) {
    std::uint32_t used[kPatchPaletteSize] = {};
    for (std::uint32_t k = first[p]; k < first[p + 1]; ++k)
      if (colour[nbr[k]] != kInvalid) ++used[colour[nbr[k]]];
    std::uint32_t best = p % kPatchPaletteSize;
    for (std::uint32_t i = 0; i < kPatchPaletteSize; ++i) {
      const std::uint32_t c = (p + i) % kPatchPaletteSize;
      if (used[c] < used[best]) best = c;
      if (used[c] == 0) break;
    }
    colour[p] = best;
  }
  return colour;
}

}  // namespace

std::array<std::uint8_t, 3> patch_palette(std::uint32_t colour_class) noexcept {
  // Tableau-like hues, light enough for dark lines, far enough apart to tell neighbours apart.
  static constexpr std::array<std::uint8_t, 3> kPalette[kPatchPaletteSize] = {
      {{0x5b, 0x8f, 0xc9}}, {{0xf2, 0x9e, 0x4c}}, {{0x6c, 0xbf, 0x6a}},
      {{0xe8, 0x6f, 0x70}}, {{0xb3, 0x8c, 0xd9}}, {{0xe9, 0xd3, 0x5b}},
      {{0x6f, 0xcf, 0xcb}}, {{0xf0, 0xa3, 0xc8}}, {{0xb8, 0x96, 0x74}}};
  return kPalette[colour_class % kPatchPaletteSize];
}

PatchView view_partition(const Adjacency& adj, const CanonicalMesh& canonical) {
  PatchView view;
  view.face_patch.assign(adj.face_count, kInvalid);
  view.edge_first.push_back(0);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> touch;  // patches sharing a schematic edge
  for (const CanonicalComponent& comp : canonical.components) {
    const LayoutMap& map = comp.map;
    if (structured_closed(comp.part)) {
      for (std::uint32_t f : map.face) view.face_patch[f] = view.patch_count;
      ++view.patch_count;
      continue;
    }
    const Schematic& s = comp.part.schematic;
    // Layout faces come patch by patch (non-hole faces in order), a*b each (grid_layout).
    std::vector<std::uint32_t> patch_of(s.face_count(), kInvalid);
    std::size_t layout_face = 0;
    for (std::uint32_t f = 0; f < s.face_count(); ++f) {
      if (s.face_hole[f]) continue;
      patch_of[f] = view.patch_count++;
      const PatchSize ps = patch_size(s, f);
      for (std::uint64_t k = 0; k < std::uint64_t{ps.a} * ps.b; ++k)
        view.face_patch[map.face[layout_face++]] = patch_of[f];
    }
    // Edge paths: each edge's inner vertices are numbered after the schematic vertices, from dart 2e.
    std::uint32_t inner = s.vertex_count;
    for (std::uint32_t e = 0; e < s.edge_count(); ++e) {
      const std::uint32_t len = s.edge_length[e];
      view.edge_path.push_back(map.vertex[s.dart_vertex[2 * e]]);
      for (std::uint32_t k = 0; k + 1 < len; ++k) view.edge_path.push_back(map.vertex[inner + k]);
      view.edge_path.push_back(map.vertex[s.dart_vertex[2 * e + 1]]);
      view.edge_first.push_back(static_cast<std::uint32_t>(view.edge_path.size()));
      inner += len - 1;
      const std::uint32_t p = patch_of[s.dart_face[2 * e]], q = patch_of[s.dart_face[2 * e + 1]];
      if (p != kInvalid && q != kInvalid && p != q) touch.emplace_back(p, q);
    }
    std::vector<std::uint8_t> on_side(s.vertex_count, 0);
    for (std::uint32_t d = 0; d < s.dart_count(); ++d)
      if (!s.face_hole[s.dart_face[d]] && !s.dart_corner[d]) on_side[s.dart_vertex[d]] = 1;
    for (std::uint32_t x = 0; x < s.vertex_count; ++x) {
      const std::uint32_t m = map.vertex[x];
      if (adj.extraordinary(m))
        view.extraordinary.push_back(m);
      else if (adj.deficiency(m) == 0 && on_side[x])
        view.t_junctions.push_back(m);
    }
  }
  view.patch_colour = colour_patches(view.patch_count, touch);
  return view;
}

Partition stored_partition(const Adjacency& adj, std::span<const TopologyCode> codes,
                           std::span<const std::uint32_t> canonical_to_mesh) {
  auto fail = [](const std::string& what) {
    throw Error(ErrorCode::kFormat, "stored partition does not lie on the decoded mesh: " + what);
  };
  auto mesh_vertex = [&](std::uint64_t c) -> std::uint32_t {
    if (canonical_to_mesh.empty()) {
      if (c >= adj.vertex_count) fail("vertex " + std::to_string(c) + " out of range");
      return static_cast<std::uint32_t>(c);
    }
    if (c >= canonical_to_mesh.size() || canonical_to_mesh[c] >= adj.vertex_count)
      fail("vertex " + std::to_string(c) + " out of range");
    return canonical_to_mesh[c];
  };
  auto halfedge = [&](std::uint32_t u, std::uint32_t v) {
    const std::uint32_t h0 = adj.vertex_halfedge[u];
    if (h0 != kInvalid) {
      std::uint32_t h = h0;
      do {
        if (adj.dest(h) == v) return h;
        h = adj.rotate(h);
      } while (h != h0);
    }
    fail("no mesh edge between vertices " + std::to_string(u) + " and " + std::to_string(v));
    return kInvalid;  // not reached
  };
  std::vector<std::uint32_t> cuts;
  std::uint64_t base = 0, edges = 0, patches = 0;  // base: the component's first layout vertex
  for (const TopologyCode& code : codes) {
    const ComponentPartition part = partition_from_code(code);
    if (structured_closed(part)) {
      base += std::uint64_t{part.a} * (part.kind == ComponentKind::kAnnulus ? part.b + 1 : part.b);
      ++patches;
      continue;
    }
    const Schematic& s = part.schematic;
    std::uint64_t inner = base + s.vertex_count;
    for (std::uint32_t e = 0; e < s.edge_count(); ++e) {
      const std::uint32_t len = s.edge_length[e];
      std::uint32_t u = mesh_vertex(base + s.dart_vertex[2 * e]);
      for (std::uint32_t k = 0; k < len; ++k) {
        const std::uint32_t w = mesh_vertex(k + 1 < len ? inner + k : base + s.dart_vertex[2 * e + 1]);
        cuts.push_back(halfedge(u, w));
        u = w;
      }
      inner += len - 1;
    }
    for (std::uint32_t f = 0; f < s.face_count(); ++f) {
      if (s.face_hole[f]) continue;
      const PatchSize ps = patch_size(s, f);
      inner += std::uint64_t{ps.a - 1} * (ps.b - 1);
    }
    base = inner;
    edges += s.edge_count();
    patches += s.patch_count();
  }
  Partition out = partition_from_cuts(adj, cuts);
  // The same cuts give the same partition; anything else is a bug, not a picture of something else.
  std::uint64_t got_edges = 0, got_patches = 0;
  for (const ComponentPartition& part : out.components) {
    got_patches += structured_closed(part) ? 1 : part.schematic.patch_count();
    got_edges += structured_closed(part) ? 0 : part.schematic.edge_count();
  }
  if (got_edges != edges || got_patches != patches)
    throw Error(ErrorCode::kInternal, "stored partition rebuilt with " + std::to_string(got_patches) +
                                          " patches and " + std::to_string(got_edges) + " edges, not " +
                                          std::to_string(patches) + " and " + std::to_string(edges));
  return out;
}

std::string layout_obj(const QuadMesh& mesh, const CanonicalMesh& canonical, const std::string& header) {
  std::string out = "# " + header + "\n";
  std::uint64_t vertices = 0, patches = 0, edges = 0;
  for (const CanonicalComponent& comp : canonical.components) {
    if (structured_closed(comp.part)) {
      ++patches;
      continue;
    }
    vertices += comp.part.schematic.vertex_count;
    edges += comp.part.schematic.edge_count();
    patches += comp.part.schematic.patch_count();
  }
  out += "# qsp layout: " + std::to_string(vertices) + " schematic vertices, " + std::to_string(edges) +
         " schematic edges, " + std::to_string(patches) +
         " patches; one face per patch, its corners and the T-junction vertices on its sides in order\n";
  for (const CanonicalComponent& comp : canonical.components) {
    if (structured_closed(comp.part)) continue;
    for (std::uint32_t x = 0; x < comp.part.schematic.vertex_count; ++x)
      append_vertex(out, mesh.positions, comp.map.vertex[x]);
  }
  std::uint64_t offset = 1, patch = 0;  // OBJ indices are 1-based
  char line[160];
  for (const CanonicalComponent& comp : canonical.components) {
    const ComponentPartition& part = comp.part;
    if (structured_closed(part)) {
      std::snprintf(
          line, sizeof line, "# patch %llu: %s component, %u x %u grid%s, no schematic vertices\n",
          static_cast<unsigned long long>(patch++), component_kind_name(part.kind), part.a, part.b,
          part.kind == ComponentKind::kTorus ? (" twist " + std::to_string(part.twist)).c_str() : "");
      out += line;
      continue;
    }
    const Schematic& s = part.schematic;
    for (std::uint32_t f = 0; f < s.face_count(); ++f) {
      if (s.face_hole[f]) continue;
      const PatchSize ps = patch_size(s, f);
      std::string face = "f", lengths;
      std::uint32_t d = s.face_dart[f];
      do {
        face += ' ';
        append_uint(face, offset + s.dart_vertex[d]);
        lengths += ' ';
        append_uint(lengths, s.edge_length[d >> 1]);
        d = s.dart_next[d];
      } while (d != s.face_dart[f]);
      std::snprintf(line, sizeof line, "# patch %llu: %u x %u grid, edge lengths",
                    static_cast<unsigned long long>(patch++), ps.a, ps.b);
      out += line + lengths + "\n" + face + "\n";
    }
    offset += s.vertex_count;
  }
  return out;
}

PatchView polygon_view(const QuadSubmesh& sub, const PatchView& quad_view, std::size_t face_count) {
  PatchView v = quad_view;
  v.face_patch.assign(face_count, kInvalid);
  for (std::size_t q = 0; q < sub.quad_face.size(); ++q)
    v.face_patch[sub.quad_face[q]] = quad_view.face_patch[q];
  for (auto* list : {&v.edge_path, &v.extraordinary, &v.t_junctions})
    for (std::uint32_t& x : *list) x = sub.vertex_original[x];
  return v;
}

namespace {

// Faces in patch order (input order within a patch), then the faces in no patch: a counting sort by
// face_patch, kInvalid counted as patch_count.
std::vector<std::uint32_t> faces_by_patch(const PatchView& view, std::vector<std::uint32_t>& first) {
  const auto key = [&view](std::uint32_t p) { return p == kInvalid ? view.patch_count : p; };
  first.assign(view.patch_count + 2, 0);
  for (std::uint32_t p : view.face_patch) ++first[key(p) + 1];
  for (std::uint32_t p = 0; p <= view.patch_count; ++p) first[p + 1] += first[p];
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1), order(view.face_patch.size());
  for (std::uint32_t f = 0; f < view.face_patch.size(); ++f) order[fill[key(view.face_patch[f])]++] = f;
  return order;
}

void append_face(std::string& out, const PolygonMesh& mesh, std::uint32_t f, std::uint32_t base) {
  for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
    out += ' ';
    append_uint(out, std::uint64_t{mesh.corners[c]} + base);
  }
}

}  // namespace

std::string patches_obj(const PolygonMesh& mesh, const PatchView& view, const std::string& header) {
  std::vector<std::uint32_t> first;
  const std::vector<std::uint32_t> order = faces_by_patch(view, first);
  const std::uint32_t others = first[view.patch_count + 1] - first[view.patch_count];
  std::string out = "# " + header + "\n# " + std::to_string(view.patch_count) +
                    " patches as groups patch_N; the " + std::to_string(view.edge_count()) +
                    " schematic edges as l polylines\n";
  if (others) out += "# " + std::to_string(others) + " faces that are not quads as group non_quads\n";
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) append_vertex(out, mesh.positions, v);
  for (std::uint32_t p = 0; p <= view.patch_count; ++p) {
    if (first[p] == first[p + 1]) continue;
    if (p < view.patch_count) {
      out += "g patch_";
      append_uint(out, p);
    } else {
      out += "g non_quads";
    }
    out += '\n';
    for (std::uint32_t k = first[p]; k < first[p + 1]; ++k) {
      out += 'f';
      append_face(out, mesh, order[k], 1);
      out += '\n';
    }
  }
  for (std::uint32_t e = 0; e < view.edge_count(); ++e) {
    out += 'l';
    for (std::uint32_t k = view.edge_first[e]; k < view.edge_first[e + 1]; ++k) {
      out += ' ';
      append_uint(out, std::uint64_t{view.edge_path[k]} + 1);
    }
    out += '\n';
  }
  return out;
}

std::string patches_ply(const PolygonMesh& mesh, const PatchView& view, const std::string& header) {
  std::string out = "ply\nformat ascii 1.0\ncomment " + header + "\n";
  if (std::find(view.face_patch.begin(), view.face_patch.end(), kInvalid) != view.face_patch.end())
    out += "comment faces that are not quads have patch -1 and a grey colour\n";
  std::uint32_t max_degree = 0;
  for (std::uint32_t f = 0; f < mesh.face_count(); ++f) max_degree = std::max(max_degree, mesh.degree(f));
  out += "element vertex " + std::to_string(mesh.vertex_count()) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(mesh.face_count()) + "\nproperty list " + (max_degree > 255 ? "uint" : "uchar") +
         " int vertex_indices\nproperty int patch\nproperty uchar red\n"
         "property uchar green\nproperty uchar blue\nend_header\n";
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    for (int c = 0; c < 3; ++c) {
      if (c) out += ' ';
      append_float(out, mesh.positions[3 * std::size_t{v} + c]);
    }
    out += '\n';
  }
  for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
    append_uint(out, mesh.degree(f));
    append_face(out, mesh, f, 0);
    const std::uint32_t p = view.face_patch[f];
    const auto rgb = p == kInvalid ? kNonQuadColour : patch_palette(view.patch_colour[p]);
    out += ' ';
    out += p == kInvalid ? std::string("-1") : std::to_string(p);
    for (std::uint8_t c : rgb) {
      out += ' ';
      append_uint(out, c);
    }
    out += '\n';
  }
  return out;
}

}  // namespace qsp
