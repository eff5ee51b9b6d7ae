// One partition's .qsp: canonical form, the layout checked against the input, the geometry searched as
// the level says (in one or both coding orders), the sections sealed into the container.
#include "codec_encode.h"

#include <algorithm>
#include <string>
#include <vector>

#include "beside.h"
#include "bytes.h"
#include "codec_sections.h"
#include "container.h"
#include "mirror.h"
#include "qsp/error.h"
#include "stencil.h"

namespace qsp {

std::string encode_partition(const QuadMesh& mesh, const Adjacency& adj, const Partition& partition,
                             const EncodeOptions& options, const Effort& effort, const EncodeTuning& tuning,
                             OrderMap* order_out, ChoiceRole role) {
  return encode_canonical(mesh, canonicalize(mesh, adj, partition), options, effort, tuning, order_out,
                          std::move(role), {}, {}, nullptr, &adj);
}

Adjacency layout_adjacency(const Adjacency& adj, const OrderMap& order) {
  const std::uint32_t nf = adj.face_count, nv = adj.vertex_count, inside = 4 * nf;
  if (order.face.size() != nf || order.rotation.size() != nf || order.vertex.size() != nv)
    throw Error(ErrorCode::kInternal, "encode: the layout's numbering does not fit the adjacency");
  const auto to = [&](std::uint32_t h) {
    if (h >= inside) return h;  // exterior (or kInvalid)
    const std::uint32_t f = h >> 2;
    return 4 * order.face[f] + ((h - order.rotation[f]) & 3u);
  };
  Adjacency out;
  out.vertex_count = nv;
  out.face_count = nf;
  out.twin.resize(adj.twin.size());
  out.origin.resize(adj.origin.size());
  for (std::uint32_t h = 0; h < adj.twin.size(); ++h) {
    out.twin[to(h)] = to(adj.twin[h]);
    out.origin[to(h)] = adj.origin[h] < nv ? order.vertex[adj.origin[h]] : adj.origin[h];
  }
  out.exterior_next = adj.exterior_next;
  out.vertex_halfedge.resize(nv);
  out.valence.resize(nv);
  out.boundary.resize(nv);
  for (std::uint32_t v = 0; v < nv; ++v) {
    const std::uint32_t w = order.vertex[v];
    out.vertex_halfedge[w] = to(adj.vertex_halfedge[v]);
    out.valence[w] = adj.valence[v];
    out.boundary[w] = adj.boundary[v];
  }
  std::vector<std::uint32_t> input_face(nf), renamed(adj.component_count, kInvalid);
  for (std::uint32_t f = 0; f < nf; ++f) input_face[order.face[f]] = f;
  out.face_component.resize(nf);
  out.component_faces.resize(adj.component_count);
  out.component_count = adj.component_count;
  std::uint32_t next = 0;
  for (std::uint32_t g = 0; g < nf; ++g) {
    const std::uint32_t c = adj.face_component[input_face[g]];
    if (renamed[c] == kInvalid) renamed[c] = next++, out.component_faces[renamed[c]] = adj.component_faces[c];
    out.face_component[g] = renamed[c];
  }
  return out;
}

// Below this many faces the topology is coded on this thread: starting one would cost more.
constexpr std::uint64_t kTopologyBesideFrom = 4096;

std::string encode_canonical(const QuadMesh& mesh, const CanonicalMesh& cm, const EncodeOptions& options,
                             const Effort& effort, const EncodeTuning& tuning, OrderMap* order_out,
                             ChoiceRole role, std::string_view polygons, std::string_view polygon_order,
                             const InteriorGeometry* interior, const Adjacency* adjacency) {
  const std::uint64_t nv = mesh.vertex_count(), nf = mesh.face_count();

  // Canonical numbering of the input, checked to be a bijection that maps every layout quad onto an
  // input quad (rotated): the decoder rebuilds exactly these quads, so the file cannot lie.
  std::vector<TopologyCode> codes;
  std::vector<ComponentPartition> parts;
  OrderMap order;
  order.vertex.assign(nv, kInvalid);
  order.face.assign(nf, kInvalid);
  order.rotation.assign(nf, 0);
  std::uint32_t vbase = 0, fbase = 0;
  auto internal = [](const std::string& why) { throw Error(ErrorCode::kInternal, "encode: " + why); };
  for (const CanonicalComponent& cc : cm.components) {
    codes.push_back(cc.code);
    parts.push_back(cc.part);
    for (std::size_t i = 0; i < cc.map.vertex.size(); ++i) {
      std::uint32_t v = cc.map.vertex[i];
      if (v >= nv || order.vertex[v] != kInvalid) internal("layout vertex map is not a bijection");
      order.vertex[v] = vbase + static_cast<std::uint32_t>(i);
    }
    for (std::size_t i = 0; i < cc.map.face.size(); ++i) {
      std::uint32_t f = cc.map.face[i];
      if (f >= nf || order.face[f] != kInvalid) internal("layout face map is not a bijection");
      order.face[f] = fbase + static_cast<std::uint32_t>(i);
      order.rotation[f] = cc.map.rotation[i] & 3u;
    }
    vbase += static_cast<std::uint32_t>(cc.map.vertex.size());
    fbase += static_cast<std::uint32_t>(cc.map.face.size());
  }
  for (std::uint32_t v : cm.unreferenced) {
    if (v >= nv || order.vertex[v] != kInvalid)
      internal("unreferenced vertex listed twice or also in a face");
    order.vertex[v] = vbase++;
  }
  if (vbase != nv || fbase != nf) internal("canonical form does not cover every vertex and face");
  if (tuning.order_known) tuning.order_known(order);
  // The topology section needs only the codes: coded on the second core while this one lays out the
  // grid and builds the stencils, which leave it idle (not where the partitions' pipelines share them).
  auto topology = beside(options.threads != 1 && !effort.all_partitions && nf >= kTopologyBesideFrom,
                         [&codes] { return encode_topology(codes); });

  const CodingOrder first = options.geometry_order.value_or(CodingOrder::kPatch);
  const auto unreferenced = static_cast<std::uint32_t>(cm.unreferenced.size());
  MeshLayout layout = assemble(parts, unreferenced, first);
  std::vector<std::uint32_t>& quads = layout.quads;
  if (quads.size() != mesh.quads.size() || layout.stencil.size() != nv ||
      (first == CodingOrder::kPatch && layout.coding.size() != nv))
    internal("layout sizes differ from the mesh");
  std::vector<std::uint32_t> canonical_to_input(nv);
  for (std::uint32_t v = 0; v < nv; ++v) canonical_to_input[order.vertex[v]] = v;
  for (std::uint32_t f = 0; f < nf; ++f) {
    std::uint32_t cf = order.face[f], r = order.rotation[f];
    for (std::uint32_t c = 0; c < 4; ++c) {
      if (canonical_to_input[quads[4 * cf + c]] != mesh.quads[4 * f + (c + r) % 4]) {
        internal("layout quad " + std::to_string(cf) + " does not match input face " + std::to_string(f));
      }
    }
  }
  // Mirror prediction (3.17): the layout's mirror symmetry, where its positions have one (quad meshes).
  const bool with_interior = interior && !interior->positions.empty();
  std::vector<MirrorSeed> seeds;
  MirrorMap mirror;
  if (effort.try_mirror && polygons.empty() && !with_interior) {
    std::vector<float> layout_positions(3 * std::size_t{nv});
    for (std::uint32_t v = 0; v < nv; ++v)
      std::copy_n(&mesh.positions[3 * std::size_t{canonical_to_input[v]}], 3,
                  &layout_positions[3 * std::size_t{v}]);
    const Adjacency layout_adj = adjacency ? layout_adjacency(*adjacency, order)
                                           : build_adjacency(quads, static_cast<std::uint32_t>(nv));
    seeds = find_mirror(quads, layout_adj, layout_positions, &mirror);
  }
  quads = {};

  // Positions in coding order: canonical order, or for patch order canonical vertex coding[k] at k; then
  // a polygon mesh's interior ones.
  auto coded_positions = [&](CodingOrder o) {
    std::vector<float> positions(3 * std::size_t{nv});
    for (std::uint32_t k = 0; k < nv; ++k) {
      const std::uint32_t v = canonical_to_input[o == CodingOrder::kPatch ? layout.coding[k] : k];
      std::copy_n(&mesh.positions[3 * std::size_t{v}], 3, &positions[3 * std::size_t{k}]);
    }
    if (with_interior)
      positions.insert(positions.end(), interior->positions.begin(), interior->positions.end());
    return positions;
  };
  // The stencils of the layout's coding positions, then of the interior vertices (their fans).
  auto with_interior_stencils = [&](MeshLayout& l) {
    if (!seeds.empty()) set_mirror_sources(l.stencil, l.coding, mirror);
    if (!with_interior) return;
    const std::vector<Stencil> more = interior_stencils(*interior->faces, nv, l.coding);
    if (3 * more.size() != interior->positions.size()) internal("interior stencils and positions differ");
    l.stencil.insert(l.stencil.end(), more.begin(), more.end());
  };
  with_interior_stencils(layout);
  GeometryOptions gopt;
  gopt.quantize_bits = options.quantize_bits;
  gopt.order = first;
  gopt.try_costly_tools = effort.try_costly_tools;
  gopt.try_mirror = !seeds.empty();
  // (Without seeds too: tests may force the tool, which then predicts nothing.)
  std::string symmetry;
  container::put_section(symmetry, container::kTagSymmetry, encode_symmetry(seeds));
  gopt.mirror_bytes = static_cast<std::uint32_t>(symmetry.size());
  // A geometry section's size with the symmetry section its mirror prediction needs.
  const auto with_symmetry = [&](const std::string& g) {
    return g.size() + ((static_cast<std::uint8_t>(g[0]) & geometry_tool::kMirror) ? symmetry.size() : 0);
  };
  gopt.tools = tuning.geometry_tools;
  gopt.header_sample = effort.header_sample;
  gopt.try_chaining = effort.try_chaining;
  gopt.repeats_must_pay = effort.repeats_must_pay;
  // One pipeline leaves the second core idle: give it the range coder from a smaller section than
  // geometry's own default, which assumes the partitions' pipelines keep both cores busy.
  constexpr std::uint64_t kCoderThreadAloneAbove = 8192;
  if (options.threads == 1) {
    gopt.coder_thread = false;
  } else if (!effort.all_partitions && nv > kCoderThreadAloneAbove) {
    gopt.coder_thread = true;
  }
  if (role.wait) gopt.choice = role.wait->get();  // rethrows what failed the encode that chooses
  GeometryChoice chosen;
  std::string geometry = encode_geometry(coded_positions(first), layout.stencil, gopt, &chosen);
  gopt.choice = chosen;
  if (role.publish && !role.publish->set) {
    role.publish->chosen.set_value(chosen);
    role.publish->set = true;
  }
  if (!options.geometry_order && effort.both_orders) {
    layout = assemble(parts, unreferenced, CodingOrder::kLayout);
    with_interior_stencils(layout);
    gopt.order = CodingOrder::kLayout;
    std::string in_layout_order =
        encode_geometry(coded_positions(CodingOrder::kLayout), layout.stencil, gopt);
    if (with_symmetry(in_layout_order) < with_symmetry(geometry)) geometry = std::move(in_layout_order);
  }

  std::string counts;
  put_varint(counts, nv);
  put_varint(counts, nf);
  put_varint(counts, codes.size());
  put_varint(counts, cm.unreferenced.size());
  counts.push_back(0);  // flags: reserved

  std::string body;
  container::put_section(body, container::kTagCounts, counts);
  container::put_section(body, container::kTagTopology, topology.get());
  container::put_section(body, container::kTagGeometry, geometry);
  if (options.keep_order) container::put_section(body, container::kTagOrder, encode_order(order));
  if (!polygon_order.empty()) container::put_section(body, container::kTagOrder, polygon_order);
  if (!polygons.empty()) container::put_section(body, container::kTagPolygons, polygons);
  if (with_interior) {
    std::string count;
    put_varint(count, interior->positions.size() / 3);
    container::put_section(body, container::kTagInterior, count);
  }
  // After every required tag below it (the attribute sections 0x06-0x0e go in before it, in tag order).
  const bool mirrored = (static_cast<std::uint8_t>(geometry[0]) & geometry_tool::kMirror) != 0;
  if (mirrored) body += symmetry;
  if (order_out) *order_out = std::move(order);
  const std::uint8_t minor = mirrored           ? kFormatMinorMirror
                             : with_interior    ? kFormatMinorInterior
                             : polygons.empty() ? kFormatMinorQuads
                                                : kFormatMinorPolygons;
  return container::seal(kFormatMajor, minor, static_cast<std::uint8_t>(options.level), body);
}

}  // namespace qsp
