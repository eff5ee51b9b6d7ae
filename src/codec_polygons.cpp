// Writing a .qsp of any polygon mesh (format 3.1): the quad submesh coded as a quad mesh's file, and the
// polygons section for the rest (docs/polygon_meshes.md, "Stage B-2").
#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <future>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "beside.h"
#include "codec_encode.h"
#include "codec_sections.h"
#include "container.h"
#include "geometry_values.h"
#include "mirror.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/permute.h"
#include "qsp/regions.h"
#include "qsp/submesh.h"

namespace qsp {
namespace {

[[noreturn]] void internal(const std::string& what) { throw Error(ErrorCode::kInternal, "encode: " + what); }

// The smallest of the three partitions' files (the first on a tie), as for quad meshes: `one(mode)`
// writes one; `keep()` is called when it is the smallest so far. A partition that breaks an invariant
// (kInternal) is passed over, but for the motorcycle graph.
template <class One, class Keep>
std::string smallest_partition(const One& one, const Keep& keep) {
  std::string best;
  for (PartitionMode m : {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge}) {
    std::string bytes;
    try {
      bytes = one(m);
    } catch (const Error& e) {
      if (e.code() != ErrorCode::kInternal || m == PartitionMode::kMotorcycle) throw;
      continue;
    }
    if (best.empty() || bytes.size() < best.size()) best = std::move(bytes), keep();
  }
  return best;
}

// Where each input face went: output face face[f], whose corner c is the input's corner (c + r) mod d;
// and each input vertex: output vertex vertex[v].
struct FaceMap {
  std::vector<std::uint32_t> face, rotation, vertex;
};

// One partition's 3.1 file of the mesh cut into `s`.
std::string encode_cut(const PolygonMesh& mesh, const QuadSubmesh& s, PartitionMode mode,
                       const EncodeOptions& options, const Effort& effort, FaceMap& map) {
  const auto nv = static_cast<std::uint32_t>(mesh.vertex_count());
  const Partition part = qsp::partition(s.adjacency, mode, s.mesh.positions);
  CanonicalRegions r = canonical_regions(mesh.face_offsets, mesh.corners, nv, mesh.positions, s,
                                         canonicalize(s.mesh, s.adjacency, part));

  // The layout as the decoder rebuilds it, and the polygons section over it.
  std::vector<ComponentPartition> parts;
  for (const CanonicalComponent& cc : r.quads.components) parts.push_back(cc.part);
  const MeshLayout layout =
      assemble(parts, static_cast<std::uint32_t>(r.quads.unreferenced.size()), std::nullopt);
  const Adjacency adj = build_adjacency(layout.quads, layout.vertex_count);
  PolygonFaces rebuilt;
  const std::string polygons = encode_polygons_section(layout.quads, adj, r.codes, &rebuilt);
  // The geometry section codes the owned interior refs' positions after the layout's (format 3.12).
  InteriorGeometry interior{&rebuilt, {}};
  for (std::uint32_t x : interior_owners(rebuilt, r.codes.layout_vertices).interior_refs) {
    const float* p = &mesh.positions[3 * std::size_t{r.interior_original[x - r.codes.layout_vertices]}];
    interior.positions.insert(interior.positions.end(), p, p + 3);
  }

  // The decoder's faces are the input's under the maps: the file cannot lie.
  if (rebuilt.vertex_count != nv)
    internal("the rebuilt mesh has " + std::to_string(rebuilt.vertex_count) + " vertices");
  const std::size_t nf = mesh.face_count();
  if (rebuilt.face_offsets.size() != nf + 1) internal("the rebuilt mesh has another face count");
  for (std::size_t f = 0; f < nf; ++f) {
    const std::uint32_t b = mesh.face_offsets[f], d = mesh.face_offsets[f + 1] - b;
    const std::uint32_t of = r.face[f], ob = rebuilt.face_offsets[of];
    if (rebuilt.face_offsets[of + 1] - ob != d) internal("face " + std::to_string(f) + " changes degree");
    for (std::uint32_t i = 0; i < d; ++i)
      if (rebuilt.corners[ob + i] != r.vertex[mesh.corners[b + (i + r.rotation[f]) % d]])
        internal("face " + std::to_string(f) + " is rebuilt on other vertices");
  }
  std::string order;
  if (options.keep_order) {
    std::vector<std::uint32_t> degree(nf);
    for (std::size_t f = 0; f < nf; ++f) degree[f] = rebuilt.face_offsets[f + 1] - rebuilt.face_offsets[f];
    order = encode_polygon_order(r.vertex, r.face, r.rotation, degree);
  }
  map.face = r.face;
  map.rotation = r.rotation;
  map.vertex = r.vertex;
  EncodeOptions quads = options;
  quads.keep_order = false;
  return encode_canonical(s.mesh, r.quads, quads, effort, {}, nullptr, {}, polygons, order, &interior);
}

// The FaceMap of an OrderMap.
FaceMap face_map(OrderMap&& order) {
  FaceMap map;
  map.face = std::move(order.face);
  map.rotation.assign(order.rotation.begin(), order.rotation.end());
  map.vertex = std::move(order.vertex);
  return map;
}

// The file of the faces and positions, and where each face went. `map_known`, if set, is called with
// that map as soon as the encode knows it, before the geometry is coded, where it does so (an all-quad
// mesh coded in one partition).
std::string encode_faces(const PolygonMesh& mesh, const EncodeOptions& options, FaceMap& map,
                         const std::function<void(const FaceMap&)>& map_known = nullptr) {
  if (mesh.positions.size() % 3 != 0)
    throw Error(ErrorCode::kUsage, "encode: positions array has a partial element");
  if (mesh.face_offsets.empty() || mesh.face_offsets.front() != 0 ||
      mesh.face_offsets.back() != mesh.corners.size())
    throw Error(ErrorCode::kUsage, "encode: face offsets do not cover the corners");
  if (mesh.vertex_count() > kMaxVertices)
    throw Error(ErrorCode::kLimit, "mesh has more than 2^31 - 1 vertices");
  if (mesh.face_count() > kMaxFaces) throw Error(ErrorCode::kLimit, "mesh has more than 2^29 - 1 faces");
  bool all_quads = true;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    if (mesh.face_offsets[f + 1] < mesh.face_offsets[f])
      throw Error(ErrorCode::kUsage, "encode: face offsets decrease at face " + std::to_string(f));
    all_quads = all_quads && mesh.face_offsets[f + 1] - mesh.face_offsets[f] == 4;
  }
  // A manifold, oriented all-quad mesh is a 3.0 file, byte for byte; what build_adjacency refuses as
  // non-manifold or mis-oriented goes through the quad submesh.
  if (all_quads) {
    try {
      OrderMap order;
      EncodeTuning tuning;
      if (map_known)
        tuning.order_known = [&map_known](const OrderMap& o) { map_known(face_map(OrderMap(o))); };
      std::string bytes = encode_tuned(QuadMesh{mesh.positions, mesh.corners}, options, tuning, &order);
      map = face_map(std::move(order));
      return bytes;
    } catch (const Error& e) {
      if (e.code() != ErrorCode::kNonManifold && e.code() != ErrorCode::kOrientation) throw;
    }
  }
  if (options.quantize_bits > 30)
    throw Error(ErrorCode::kUsage, "encode: quantize_bits " + std::to_string(options.quantize_bits) +
                                       " is not 0 (lossless) to 30");
  const auto nv = static_cast<std::uint32_t>(mesh.vertex_count());
  const QuadSubmesh s = quad_submesh(mesh.face_offsets, mesh.corners, nv, mesh.positions);
  const Effort effort = level_effort(options.level, s.mesh.vertex_count());
  if (options.partition || !effort.all_partitions)
    return encode_cut(mesh, s, options.partition.value_or(PartitionMode::kMotorcycle), options, effort, map);
  // The highest levels keep the smallest of the three partitions' files.
  FaceMap this_map;
  return smallest_partition(
      [&](PartitionMode m) { return encode_cut(mesh, s, m, options, effort, this_map); },
      [&] { map = std::move(this_map); });
}

// Per output face (the decoder's order before any order section), the input face `map` sent there.
std::vector<std::uint32_t> input_faces(const FaceMap& map, std::size_t nf) {
  if (map.face.size() != nf || map.rotation.size() != nf) internal("the face map has another face count");
  std::vector<std::uint32_t> input_face(nf, kInvalid);
  for (std::size_t f = 0; f < nf; ++f) {
    if (map.face[f] >= nf || input_face[map.face[f]] != kInvalid)
      internal("the face map is not a permutation");
    input_face[map.face[f]] = static_cast<std::uint32_t>(f);
  }
  return input_face;
}

// The output corners (the decoder's order before any order section) of `mesh` whose faces went where
// `map` says: face offsets, each corner's input vertex (the decoder's vertices are the same up to
// numbering) and input corner.
struct OutputCorners {
  std::vector<std::uint32_t> offsets, vertices, input;
};
OutputCorners output_corners(const PolygonMesh& mesh, const FaceMap& map,
                             std::span<const std::uint32_t> input_face) {
  const std::size_t nf = mesh.face_count();
  OutputCorners out;
  out.offsets.assign(nf + 1, 0);
  out.vertices.resize(mesh.corners.size());
  out.input.resize(mesh.corners.size());
  for (std::size_t g = 0; g < nf; ++g) {
    const std::uint32_t f = input_face[g], b = mesh.face_offsets[f], d = mesh.degree(f);
    out.offsets[g + 1] = out.offsets[g] + d;
    for (std::uint32_t c = 0; c < d; ++c) {
      const std::uint32_t from = b + (c + map.rotation[f]) % d;
      out.vertices[out.offsets[g] + c] = mesh.corners[from];
      out.input[out.offsets[g] + c] = from;
    }
  }
  return out;
}

// The positions the decoder of a file without a polygons section predicts corner values from, per
// input vertex: lossless ones are the input's; quantized ones on the grid over all of them.
std::vector<float> quad_file_positions(const PolygonMesh& mesh, const EncodeOptions& options) {
  if (!options.quantize_bits) return mesh.positions;
  const Grid grid = make_grid(mesh.positions, options.quantize_bits);
  std::vector<float> out(mesh.positions.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const int axis = static_cast<int>(i % 3);
    out[i] = grid.value(axis, grid.quantize(axis, mesh.positions[i], options.quantize_bits));
  }
  return out;
}

// The positions the decoder of `file` predicts corner values from, per input vertex: lossless ones are
// the input's; quantized ones as the decoder rebuilds them.
std::vector<float> decoder_positions(const PolygonMesh& mesh, const OutputCorners& oc,
                                     const EncodeOptions& options, std::string_view file) {
  // A file without a polygons section holds every position in its geometry section, on the grid over
  // all of them: the decoder's values, computed as it computes them without decoding the file (that
  // decode was a fifth of compressing keenan_spot with its UVs).
  if (!options.quantize_bits || container::parse(file).find(container::kTagPolygons) == nullptr)
    return quad_file_positions(mesh, options);
  DecodeLimits all;
  all.max_vertices = kMaxVertices;
  all.max_faces = kMaxFaces;
  const PolygonMesh d = decode_polygons(file, all);
  if (d.corners.size() != oc.vertices.size() || d.positions.size() != mesh.positions.size())
    internal("the decoded mesh has another size");
  if (options.keep_order) return d.positions;         // numbered as the input
  std::vector<float> decoded(mesh.positions.size());  // numbered by the decoder: its corners are the output's
  for (std::size_t k = 0; k < oc.vertices.size(); ++k)
    std::copy_n(&d.positions[3 * std::size_t{d.corners[k]}], 3, &decoded[3 * std::size_t{oc.vertices[k]}]);
  return decoded;
}

// The exact positions section: each input vertex's binary32 and exact values at its output vertex.
std::string exact_section(const PolygonMesh& mesh, const FaceMap& map) {
  const std::size_t nv = mesh.vertex_count();
  if (map.vertex.size() != nv) internal("the vertex map has another vertex count");
  std::vector<float> positions(3 * nv);
  std::vector<double> exact(3 * nv);
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t o = map.vertex[v];
    if (o >= nv) internal("the vertex map names a vertex out of range");
    std::copy_n(&mesh.positions[3 * v], 3, &positions[3 * o]);
    std::copy_n(&mesh.positions64[3 * v], 3, &exact[3 * o]);
  }
  return encode_exact_section(positions, exact);
}

// The colours section: each input vertex's colour at its output vertex, each input face's at its output
// face.
std::string colors_section(const PolygonMesh& mesh, const FaceMap& map, const OutputCorners& oc,
                           std::span<const std::uint32_t> input_face, std::uint32_t quantize_bits) {
  const std::size_t nv = mesh.vertex_count(), Kv = mesh.vertex_color_components,
                    Kf = mesh.face_color_components;
  std::vector<float> vertex(mesh.vertex_colors.size()), face(mesh.face_colors.size());
  for (std::size_t v = 0; v < nv && Kv; ++v)
    std::copy_n(&mesh.vertex_colors[Kv * v], Kv, &vertex[Kv * map.vertex[v]]);
  for (std::size_t g = 0; g < input_face.size() && Kf; ++g)
    std::copy_n(&mesh.face_colors[Kf * input_face[g]], Kf, &face[Kf * g]);
  std::vector<std::uint32_t> corner_vertices(oc.vertices.size());  // output vertices: the walk compares them
  for (std::size_t k = 0; k < oc.vertices.size(); ++k) corner_vertices[k] = map.vertex[oc.vertices[k]];
  return encode_colors_section(oc.offsets, corner_vertices, static_cast<std::uint32_t>(nv),
                               mesh.vertex_color_components, vertex, mesh.face_color_components, face,
                               quantize_bits);
}

// A section of values per corner (texture coordinates, normals) over the output corners; `mirror` as
// encode_texcoords_section's, per input vertex.
std::string corner_values_section(const PolygonMesh& mesh, const OutputCorners& oc,
                                  std::span<const float> positions, std::uint8_t components,
                                  std::span<const float> values, std::span<const std::uint32_t> corner_values,
                                  const EncodeOptions& options, std::uint32_t quantize_bits,
                                  const CornerValueWords& words, std::span<const std::uint32_t> mirror = {}) {
  std::vector<std::uint32_t> named(oc.input.size());
  for (std::size_t k = 0; k < oc.input.size(); ++k) named[k] = corner_values[oc.input[k]];
  return encode_texcoords_section(oc.offsets, oc.vertices, static_cast<std::uint32_t>(mesh.vertex_count()),
                                  positions, components, values, named, options.keep_order, quantize_bits,
                                  words, level_effort(options.level, mesh.vertex_count()).header_sample,
                                  mirror);
}

// Each input vertex's mirror image under `file`'s symmetry section (3.17), as the decoder finds it on the
// output quads, for the texture coordinates' mirror prediction (3.18); empty without one or beside a
// polygons section (whose output vertices are not the layout's).
std::vector<std::uint32_t> input_mirror(const PolygonMesh& mesh, const FaceMap& map, const OutputCorners& oc,
                                        std::string_view file) {
  const container::File f = container::parse(file);
  const container::Section* symmetry = f.find(container::kTagSymmetry);
  if (!symmetry || f.find(container::kTagPolygons)) return {};
  const auto nv = static_cast<std::uint32_t>(mesh.vertex_count());
  const auto nf = static_cast<std::uint32_t>(mesh.face_count());
  if (oc.vertices.size() != 4 * std::size_t{nf} || map.vertex.size() != nv)
    internal("a file with a symmetry section has faces other than quads");
  std::vector<std::uint32_t> quads(oc.vertices.size());
  for (std::size_t k = 0; k < quads.size(); ++k) quads[k] = map.vertex[oc.vertices[k]];
  const MirrorMap mirror =
      section_mirror(symmetry->payload, symmetry->payload_offset, quads, build_adjacency(quads, nv));
  const std::vector<std::uint32_t> input = inverse_permutation(map.vertex);
  std::vector<std::uint32_t> out(nv, kInvalid);
  for (std::uint32_t v = 0; v < nv; ++v)
    if (const std::uint32_t m = mirror.image[map.vertex[v]]; m != kInvalid) out[v] = input[m];
  return out;
}

// The per-corner sections coded beside the geometry (encode_polygons).
struct EarlySections {
  std::string texcoords, normals;
};

// Whether each binary32 is the one nearest its exact value (ties to even), as the exact sections require.
bool nearest(std::span<const float> values, std::span<const double> exact) {
  for (std::size_t i = 0; i < exact.size(); ++i)
    if (std::bit_cast<std::uint32_t>(static_cast<float>(exact[i])) != std::bit_cast<std::uint32_t>(values[i]))
      return false;
  return true;
}
void round_to(std::vector<float>& values, const std::vector<double>& exact) {
  for (std::size_t i = 0; i < exact.size(); ++i) values[i] = static_cast<float>(exact[i]);
}

// The exact values section (format 3.13) of the attribute arrays whose exact values say more than their
// binary32s and that `o` keeps exactly: over the arrays as the decoder returns `file` (after any order
// section), so the file is decoded and each input value found at its output place. With the order kept
// they are the input's own; else through the corners (texture coordinates and normals: an output
// corner's value is its input corner's), the vertex map and the output faces, and values no corner
// names matched by their binary32s. Empty when no array needs it.
std::string exact_values_section(const PolygonMesh& mesh, const EncodeOptions& o, const FaceMap& map,
                                 const OutputCorners& oc, std::span<const std::uint32_t> input_face,
                                 const std::string& file) {
  const bool uv = o.quantize_texcoord_bits == 0 && exact_needed(mesh.texcoords, mesh.texcoords64);
  const bool normal = o.quantize_normal_bits == 0 && exact_needed(mesh.normals, mesh.normals64);
  const bool vertex = o.quantize_color_bits == 0 && exact_needed(mesh.vertex_colors, mesh.vertex_colors64);
  const bool face = o.quantize_color_bits == 0 && exact_needed(mesh.face_colors, mesh.face_colors64);
  if (!uv && !normal && !vertex && !face) return {};
  DecodeLimits all;
  all.max_vertices = kMaxVertices;
  all.max_faces = kMaxFaces;
  all.max_texcoords = all.max_normals = kMaxVertices;
  const PolygonMesh d = decode_polygons(file, all);
  // Per output value its input value, through the corners; values no corner names by their binary32s.
  const auto through_corners = [&](std::span<const float> values, std::span<const double> exact,
                                   std::span<const std::uint32_t> corner_in,
                                   std::span<const std::uint32_t> corner_out,
                                   std::span<const float> out_values, std::size_t k) {
    if (o.keep_order) return std::vector<double>(exact.begin(), exact.end());
    const std::size_t n = values.size() / k;
    if (out_values.size() != values.size() || corner_out.size() != oc.input.size())
      internal("the decoded values have another size");
    std::vector<std::uint32_t> from(n, kInvalid);
    std::vector<bool> named(n);
    for (std::size_t c = 0; c < corner_out.size(); ++c) {
      const std::uint32_t t = corner_out[c], in = corner_in[oc.input[c]];
      if (t == kInvalid) continue;
      if (from[t] != kInvalid && from[t] != in) internal("an output value has two input values");
      from[t] = in, named[in] = true;
    }
    std::vector<std::uint32_t> free_out, free_in;
    for (std::uint32_t t = 0; t < n; ++t) {
      if (from[t] == kInvalid) free_out.push_back(t);
      if (!named[t]) free_in.push_back(t);
    }
    // By binary32s, then (input) by exact values, so equal binary32s get their exact values in one
    // order whatever the input's numbering: the output's are alike but for their places.
    const auto by_bits = [&](std::span<const float> v, std::span<const double> e) {
      return [v, e, k](std::uint32_t a, std::uint32_t b) {
        for (std::size_t i = 0; i < k; ++i) {
          const auto x = std::bit_cast<std::uint32_t>(v[k * a + i]),
                     y = std::bit_cast<std::uint32_t>(v[k * b + i]);
          if (x != y) return x < y;
        }
        for (std::size_t i = 0; i < k && !e.empty(); ++i) {
          const auto x = std::bit_cast<std::uint64_t>(e[k * a + i]),
                     y = std::bit_cast<std::uint64_t>(e[k * b + i]);
          if (x != y) return x < y;
        }
        return a < b;
      };
    };
    std::sort(free_out.begin(), free_out.end(), by_bits(out_values, {}));
    std::sort(free_in.begin(), free_in.end(), by_bits(values, exact));
    if (free_out.size() != free_in.size()) internal("values no corner names differ in number");
    for (std::size_t i = 0; i < free_out.size(); ++i) from[free_out[i]] = free_in[i];
    std::vector<double> out(exact.size());
    for (std::size_t t = 0; t < n; ++t) {
      for (std::size_t i = 0; i < k; ++i)
        if (std::bit_cast<std::uint32_t>(out_values[k * t + i]) !=
            std::bit_cast<std::uint32_t>(values[k * from[t] + i]))
          internal("an output value is not its input value's binary32");
      std::copy_n(&exact[k * from[t]], k, &out[k * t]);
    }
    return out;
  };
  std::vector<double> uv64, normal64, vertex64, face64;
  if (uv)
    uv64 = through_corners(mesh.texcoords, mesh.texcoords64, mesh.corner_texcoords, d.corner_texcoords,
                           d.texcoords, mesh.texcoord_components);
  if (normal)
    normal64 =
        through_corners(mesh.normals, mesh.normals64, mesh.corner_normals, d.corner_normals, d.normals, 3);
  const std::size_t kv = mesh.vertex_color_components, kf = mesh.face_color_components;
  if (vertex) {
    vertex64.resize(mesh.vertex_colors64.size());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
      std::copy_n(&mesh.vertex_colors64[kv * v], kv, &vertex64[kv * (o.keep_order ? v : map.vertex[v])]);
  }
  if (face) {
    face64.resize(mesh.face_colors64.size());
    for (std::size_t g = 0; g < input_face.size(); ++g) {
      const std::size_t f = input_face[g];
      std::copy_n(&mesh.face_colors64[kf * f], kf, &face64[kf * (o.keep_order ? f : g)]);
    }
  }
  const ExactArray arrays[] = {{d.texcoords, uv64, mesh.texcoord_components},
                               {d.normals, normal64, 3},
                               {d.vertex_colors, vertex64, kv},
                               {d.face_colors, face64, kf}};
  return encode_exact_values_section(arrays);
}

}  // namespace

std::string encode_polygons(const PolygonMesh& mesh, const EncodeOptions& options) {
  const OneThread one_thread(options.threads == 1);
  const bool texcoords = mesh.texcoord_components != 0;
  if (texcoords ? mesh.texcoord_components > 3 || mesh.texcoords.size() % mesh.texcoord_components != 0 ||
                      mesh.corner_texcoords.size() != mesh.corners.size()
                : !mesh.texcoords.empty() || !mesh.corner_texcoords.empty())
    throw Error(ErrorCode::kUsage, "encode: texture coordinate arrays disagree with their component count");
  if (texcoords) {
    const std::size_t count = mesh.texcoords.size() / mesh.texcoord_components;
    for (std::size_t c = 0; c < mesh.corner_texcoords.size(); ++c)
      if (mesh.corner_texcoords[c] != kInvalid && mesh.corner_texcoords[c] >= count)
        throw Error(ErrorCode::kUsage, "encode: corner " + std::to_string(c) + " names texture coordinate " +
                                           std::to_string(mesh.corner_texcoords[c]) + " of " +
                                           std::to_string(count));
  }
  if (!mesh.positions64.empty() && mesh.positions64.size() != mesh.positions.size())
    throw Error(ErrorCode::kUsage, "encode: exact positions are not 3 per vertex");
  // Lossless: the positions coded are the binary32 nearest the exact values (format-spec, "Exact
  // positions section"), which a reader's binary32 of the text may miss by an ulp.
  if (!mesh.positions64.empty() && !options.quantize_bits && !nearest(mesh.positions, mesh.positions64)) {
    PolygonMesh rounded = mesh;
    round_to(rounded.positions, rounded.positions64);
    return encode_polygons(rounded, options);
  }
  // So are texture coordinates, normals and colours with exact values (the exact values section).
  for (const auto& [values, exact] :
       {std::pair{&mesh.texcoords, &mesh.texcoords64}, std::pair{&mesh.normals, &mesh.normals64},
        std::pair{&mesh.vertex_colors, &mesh.vertex_colors64},
        std::pair{&mesh.face_colors, &mesh.face_colors64}}) {
    if (!exact->empty() && exact->size() != values->size())
      throw Error(ErrorCode::kUsage, "encode: exact attribute values are not one per value");
    if (!exact->empty() && !nearest(*values, *exact)) {
      PolygonMesh rounded = mesh;
      round_to(rounded.texcoords, rounded.texcoords64);
      round_to(rounded.normals, rounded.normals64);
      round_to(rounded.vertex_colors, rounded.vertex_colors64);
      round_to(rounded.face_colors, rounded.face_colors64);
      return encode_polygons(rounded, options);
    }
  }
  const bool labels = mesh.has_labels();
  const bool normals = !mesh.normals.empty() || !mesh.corner_normals.empty();
  if (normals && (mesh.normals.size() % 3 != 0 || mesh.corner_normals.size() != mesh.corners.size()))
    throw Error(ErrorCode::kUsage, "encode: normal arrays disagree with the corners");
  for (std::size_t c = 0; c < mesh.corner_normals.size(); ++c)
    if (mesh.corner_normals[c] != kInvalid && mesh.corner_normals[c] >= mesh.normals.size() / 3)
      throw Error(ErrorCode::kUsage, "encode: corner " + std::to_string(c) + " names normal " +
                                         std::to_string(mesh.corner_normals[c]) + " of " +
                                         std::to_string(mesh.normals.size() / 3));
  const bool colors = mesh.vertex_color_components != 0 || mesh.face_color_components != 0;
  const bool properties = !mesh.vertex_properties.empty() || !mesh.face_properties.empty();
  if (mesh.vertex_colors.size() != mesh.vertex_color_components * mesh.vertex_count() ||
      mesh.face_colors.size() != mesh.face_color_components * mesh.face_count())
    throw Error(ErrorCode::kUsage, "encode: colour arrays disagree with the vertex and face counts");
  const auto whole = [&](const EncodeOptions& o) {
    // The per-corner sections need only the face map and the decoder's positions, which for a file
    // without a polygons section come from the grid: where the encode knows the map before the
    // geometry, they are coded beside it (the UVs were a third of compressing mh_female_generic's whole
    // OBJ). Checked against the final file: a map that differs, or a polygons section (neither happens),
    // codes them again below.
    FaceMap early_map;
    Beside<EarlySections> early;
    const auto start_early = [&](const FaceMap& m) {
      early_map = m;
      early = beside(o.threads != 1, [&] {
        EarlySections e;
        const std::vector<std::uint32_t> in_face = input_faces(early_map, mesh.face_count());
        const OutputCorners corners = output_corners(mesh, early_map, in_face);
        const std::vector<float> at = quad_file_positions(mesh, o);
        if (texcoords)
          e.texcoords =
              corner_values_section(mesh, corners, at, mesh.texcoord_components, mesh.texcoords,
                                    mesh.corner_texcoords, o, o.quantize_texcoord_bits, kTexcoordWords);
        if (normals)
          e.normals = corner_values_section(mesh, corners, at, 3, mesh.normals, mesh.corner_normals, o,
                                            o.quantize_normal_bits, kNormalWords);
        return e;
      });
    };
    FaceMap map;
    std::string bytes = encode_faces(mesh, o, map,
                                     texcoords || normals ? std::function<void(const FaceMap&)>(start_early)
                                                          : std::function<void(const FaceMap&)>());
    std::optional<EarlySections> ready;
    if (early.valid()) {
      EarlySections e = early.get();
      if (early_map.face == map.face && early_map.rotation == map.rotation &&
          early_map.vertex == map.vertex &&
          container::parse(bytes).find(container::kTagPolygons) == nullptr)  // its positions are the grid's
        ready = std::move(e);
    }
    const bool exact = !mesh.positions64.empty() && o.quantize_bits == 0;
    const bool statements = o.keep_order && statements_needed(mesh);
    const bool exact_values = !mesh.texcoords64.empty() || !mesh.normals64.empty() ||
                              !mesh.vertex_colors64.empty() || !mesh.face_colors64.empty();
    if (!texcoords && !normals && !labels && mesh.tags.empty() && !exact && mesh.kept_lines.empty() &&
        !colors && !statements && !properties && mesh.ply_info.empty())
      return bytes;
    const std::vector<std::uint32_t> input_face = input_faces(map, mesh.face_count());
    const OutputCorners oc =
        texcoords || normals || colors ? output_corners(mesh, map, input_face) : OutputCorners{};
    const std::vector<float> positions =
        (texcoords || normals) && !ready ? decoder_positions(mesh, oc, o, bytes) : std::vector<float>{};
    if (texcoords) {
      // Predicted from their mirror images too (3.18) where the file has a mirror and the level codes every
      // prediction in full: beside the geometry they are coded before the mirror is known.
      const std::vector<std::uint32_t> mirror = level_effort(o.level, mesh.vertex_count()).header_sample == 0
                                                    ? input_mirror(mesh, map, oc, bytes)
                                                    : std::vector<std::uint32_t>{};
      const std::string section =
          ready && mirror.empty()
              ? ready->texcoords
              : corner_values_section(mesh, oc,
                                      positions.empty() ? decoder_positions(mesh, oc, o, bytes) : positions,
                                      mesh.texcoord_components, mesh.texcoords, mesh.corner_texcoords, o,
                                      o.quantize_texcoord_bits, kTexcoordWords, mirror);
      bytes =
          container::with_section(bytes, container::kTagTexcoords, section, texcoords_section_minor(section));
    }
    if (labels) {
      const std::string section = encode_labels_section(mesh, input_face);
      bytes = container::with_section(bytes, container::kTagLabels, section, labels_section_minor(section));
    }
    if (!mesh.tags.empty())
      bytes = container::with_section(bytes, container::kTagTags,
                                      encode_tags_section(mesh.tags, map.vertex, map.face, o.keep_order),
                                      kFormatMinorTags);
    if (normals) {
      const std::string section =
          ready ? ready->normals
                : corner_values_section(mesh, oc, positions, 3, mesh.normals, mesh.corner_normals, o,
                                        o.quantize_normal_bits, kNormalWords);
      bytes = container::with_section(bytes, container::kTagNormals, section, normals_section_minor(section));
    }
    if (exact)
      bytes =
          container::with_section(bytes, container::kTagExact, exact_section(mesh, map), kFormatMinorExact);
    if (colors)
      bytes = container::with_section(bytes, container::kTagColors,
                                      colors_section(mesh, map, oc, input_face, o.quantize_color_bits),
                                      kFormatMinorColors);
    if (!mesh.kept_lines.empty())
      bytes = container::with_section(bytes, container::kTagKeptLines,
                                      encode_kept_lines_section(mesh.kept_lines), kFormatMinorKeptLines);
    if (!mesh.ply_info.empty())
      bytes = container::with_section(bytes, container::kTagPlyInfo, encode_ply_info_section(mesh.ply_info),
                                      kFormatMinorPlyInfo);
    if (statements)
      bytes = container::with_section(bytes, container::kTagStatements,
                                      encode_statements_section(mesh, input_face), kFormatMinorStatements);
    if (exact_values) {
      const std::string section = exact_values_section(mesh, o, map, oc, input_face, bytes);
      if (!section.empty())
        bytes = container::with_section(bytes, container::kTagExactValues, section, kFormatMinorExactValues);
    }
    if (properties) {
      // Per output vertex and face, as the colours: the decoder applies any order section after them.
      const std::vector<std::uint32_t> vertex_from = inverse_permutation(map.vertex);
      bytes = container::with_section(
          bytes, container::kTagProperties,
          encode_properties_section(permute_properties(mesh.vertex_properties, vertex_from),
                                    permute_properties(mesh.face_properties, input_face), mesh.vertex_count(),
                                    mesh.face_count()),
          kFormatMinorProperties);
    }
    return bytes;
  };
  // The levels that try every partition keep the smallest whole file: with texture coordinates the
  // partition that codes the faces smallest need not be the one whose corner order codes the UVs best.
  if (!texcoords || options.partition || !level_effort(options.level, mesh.vertex_count()).all_partitions)
    return whole(options);
  return smallest_partition(
      [&](PartitionMode m) {
        EncodeOptions one = options;
        one.partition = m;
        return whole(one);
      },
      [] {});
}

}  // namespace qsp
