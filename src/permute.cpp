// Applying a renumbering to a mesh (qsp/permute.h): positions and faces moved, vertex indices in the
// faces rewritten, corners rotated.
#include "qsp/permute.h"

#include <algorithm>
#include <string>
#include <vector>

#include "qsp/error.h"

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

}  // namespace qsp
