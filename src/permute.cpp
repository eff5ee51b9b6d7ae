// Applying a renumbering to a mesh (qsp/permute.h): positions and faces moved, vertex indices in the
// faces rewritten, corners rotated.
#include "qsp/permute.h"

#include <algorithm>
#include <string>
#include <vector>

#include "qsp/error.h"
#include "qsp/polymesh.h"

namespace qsp {

std::vector<std::uint32_t> inverse_permutation(std::span<const std::uint32_t> p) {
  std::vector<std::uint32_t> inverse(p.size(), kInvalid);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i] >= p.size() || inverse[p[i]] != kInvalid)
      throw Error(ErrorCode::kUsage, "permute: entry " + std::to_string(i) + " (" + std::to_string(p[i]) +
                                         ") makes the map no permutation of 0.." + std::to_string(p.size()) +
                                         "-1");
    inverse[p[i]] = static_cast<std::uint32_t>(i);
  }
  return inverse;
}

QuadMesh permute(const QuadMesh& mesh, const Renumbering& r) {
  const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
  if (r.vertex_from.size() != nv || r.face_from.size() != nf ||
      (!r.rotation.empty() && r.rotation.size() != nf))
    throw Error(ErrorCode::kUsage, "permute: maps of " + std::to_string(r.vertex_from.size()) +
                                       " vertices, " + std::to_string(r.face_from.size()) + " faces and " +
                                       std::to_string(r.rotation.size()) + " rotations for a mesh of " +
                                       std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces");
  const std::vector<std::uint32_t> to = inverse_permutation(r.vertex_from);  // old vertex -> new
  (void)inverse_permutation(r.face_from);                                    // checks it is one
  QuadMesh out;
  out.positions.resize(mesh.positions.size());
  for (std::size_t i = 0; i < nv; ++i)
    std::copy_n(&mesh.positions[3 * std::size_t{r.vertex_from[i]}], 3, &out.positions[3 * i]);
  out.quads.resize(mesh.quads.size());
  for (std::size_t f = 0; f < nf; ++f) {
    const std::uint32_t* from = &mesh.quads[4 * std::size_t{r.face_from[f]}];
    const std::uint32_t turn = r.rotation.empty() ? 0 : r.rotation[f];
    for (std::uint32_t c = 0; c < 4; ++c) {
      const std::uint32_t v = from[(r.reverse ? turn - c : c + turn) & 3u];
      if (v >= nv)
        throw Error(ErrorCode::kBadIndex,
                    "face " + std::to_string(r.face_from[f]) + " uses vertex " + std::to_string(v) + " of " +
                        std::to_string(nv),
                    r.face_from[f]);
      out.quads[4 * f + c] = to[v];
    }
  }
  return out;
}

std::vector<ValueProperty> permute_properties(const std::vector<ValueProperty>& props,
                                              std::span<const std::uint32_t> from) {
  std::vector<ValueProperty> out;
  for (const ValueProperty& p : props) {
    bool bad = p.list ? p.offsets.size() != from.size() + 1 || p.offsets.front() != 0 ||
                            p.offsets.back() != p.values.size()
                      : p.values.size() != from.size();
    for (std::size_t e = 0; p.list && !bad && e < from.size(); ++e)
      bad = p.offsets[e + 1] < p.offsets[e] || from[e] >= from.size();
    for (std::size_t e = 0; !p.list && !bad && e < from.size(); ++e) bad = from[e] >= from.size();
    if (bad)
      throw Error(ErrorCode::kUsage, "permute: property '" + p.name + "' disagrees with its element count");
    ValueProperty& q = out.emplace_back(p);
    if (!p.list) {
      for (std::size_t e = 0; e < from.size(); ++e) q.values[e] = p.values[from[e]];
      continue;
    }
    q.values.clear();
    for (std::size_t e = 0; e < from.size(); ++e) {
      q.values.insert(q.values.end(), p.values.begin() + p.offsets[from[e]],
                      p.values.begin() + p.offsets[from[e] + 1]);
      q.offsets[e + 1] = static_cast<std::uint32_t>(q.values.size());
    }
  }
  return out;
}

PolygonMesh permute(const PolygonMesh& mesh, const PolygonRenumbering& r) {
  const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
  if (r.vertex_from.size() != nv || r.face_from.size() != nf || (!r.first.empty() && r.first.size() != nf))
    throw Error(ErrorCode::kUsage, "permute: maps of " + std::to_string(r.vertex_from.size()) +
                                       " vertices, " + std::to_string(r.face_from.size()) + " faces and " +
                                       std::to_string(r.first.size()) + " first corners for a mesh of " +
                                       std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces");
  if ((!mesh.positions64.empty() && mesh.positions64.size() != 3 * nv) ||
      (!mesh.texcoords64.empty() && mesh.texcoords64.size() != mesh.texcoords.size()) ||
      (!mesh.normals64.empty() && mesh.normals64.size() != mesh.normals.size()) ||
      (!mesh.vertex_colors64.empty() && mesh.vertex_colors64.size() != mesh.vertex_colors.size()) ||
      (!mesh.face_colors64.empty() && mesh.face_colors64.size() != mesh.face_colors.size()) ||
      mesh.vertex_colors.size() != mesh.vertex_color_components * nv ||
      mesh.face_colors.size() != mesh.face_color_components * nf ||
      (!mesh.corner_texcoords.empty() && mesh.corner_texcoords.size() != mesh.corners.size()) ||
      (!mesh.corner_normals.empty() && mesh.corner_normals.size() != mesh.corners.size()))
    throw Error(ErrorCode::kUsage,
                "permute: attribute arrays disagree with the mesh's vertices, faces or corners");
  for (const FaceLabels* l : {&mesh.objects, &mesh.groups, &mesh.materials, &mesh.smoothing})
    if (!l->face.empty() && l->face.size() != nf)
      throw Error(ErrorCode::kUsage, "permute: a face label array disagrees with the faces");
  const std::vector<std::uint32_t> to = inverse_permutation(r.vertex_from);  // old vertex -> new
  const std::vector<std::uint32_t> face_to = inverse_permutation(r.face_from);
  PolygonMesh out;
  const auto per_vertex = [&](const auto& from, std::size_t k, auto& into) {
    into.resize(from.size());
    for (std::size_t i = 0; i < nv && k; ++i) std::copy_n(&from[k * r.vertex_from[i]], k, &into[k * i]);
  };
  per_vertex(mesh.positions, 3, out.positions);
  per_vertex(mesh.positions64, mesh.positions64.empty() ? 0 : 3, out.positions64);
  out.vertex_color_components = mesh.vertex_color_components;
  per_vertex(mesh.vertex_colors, mesh.vertex_color_components, out.vertex_colors);
  per_vertex(mesh.vertex_colors64, mesh.vertex_colors64.empty() ? 0 : mesh.vertex_color_components,
             out.vertex_colors64);
  const bool texcoords = !mesh.corner_texcoords.empty(), normals = !mesh.corner_normals.empty();
  out.corners.reserve(mesh.corners.size());
  out.face_offsets.reserve(nf + 1);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::uint32_t g = r.face_from[f], d = mesh.degree(g), s = r.first.empty() ? 0 : r.first[f];
    if (s >= d)
      throw Error(ErrorCode::kUsage, "permute: face " + std::to_string(f) + " starts at corner " +
                                         std::to_string(s) + " of " + std::to_string(d));
    for (std::uint32_t c = 0; c < d; ++c) {
      const std::uint32_t from = mesh.face_offsets[g] + (r.reverse ? (s + d - c) % d : (c + s) % d);
      if (mesh.corners[from] >= nv)
        throw Error(ErrorCode::kBadIndex,
                    "face " + std::to_string(g) + " uses vertex " + std::to_string(mesh.corners[from]) +
                        " of " + std::to_string(nv),
                    g);
      out.corners.push_back(to[mesh.corners[from]]);
      if (texcoords) out.corner_texcoords.push_back(mesh.corner_texcoords[from]);
      if (normals) out.corner_normals.push_back(mesh.corner_normals[from]);
    }
    out.face_offsets.push_back(static_cast<std::uint32_t>(out.corners.size()));
  }
  out.texcoord_components = mesh.texcoord_components;
  out.texcoords = mesh.texcoords;
  out.texcoords64 = mesh.texcoords64;
  out.normals = mesh.normals;
  out.normals64 = mesh.normals64;
  const std::size_t kf = mesh.face_color_components;
  out.face_color_components = mesh.face_color_components;
  out.face_colors.resize(mesh.face_colors.size());
  out.face_colors64.resize(mesh.face_colors64.size());
  for (std::size_t f = 0; f < nf && kf; ++f) {
    std::copy_n(&mesh.face_colors[kf * r.face_from[f]], kf, &out.face_colors[kf * f]);
    if (!mesh.face_colors64.empty())
      std::copy_n(&mesh.face_colors64[kf * r.face_from[f]], kf, &out.face_colors64[kf * f]);
  }
  for (auto [from, into] :
       {std::pair{&mesh.objects, &out.objects}, std::pair{&mesh.groups, &out.groups},
        std::pair{&mesh.materials, &out.materials}, std::pair{&mesh.smoothing, &out.smoothing}}) {
    into->names = from->names;
    if (from->face.empty()) continue;
    into->face.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) into->face[f] = from->face[r.face_from[f]];
  }
  out.vertex_properties = permute_properties(mesh.vertex_properties, r.vertex_from);
  out.face_properties = permute_properties(mesh.face_properties, r.face_from);
  out.material_libraries = mesh.material_libraries;
  out.kept_lines = mesh.kept_lines;
  out.ply_info = mesh.ply_info;
  out.tags = mesh.tags;
  if (r.renumber_tags) renumber_tags(out.tags, to, face_to);
  return out;
}

}  // namespace qsp
