// libFuzzer target: quad_submesh on arbitrary polygon arrays. Bytes: the vertex count (1 + first byte
// % 64), then per face a degree byte (1 + b % 9, so degrees below 3 occur) and that many vertex
// bytes (b % (vertex count + 2), so indices out of range occur). Properties: only kBadIndex or
// kDegenerateFace errors; an accepted mesh glues back exactly (every corner, every face once), its
// quad submesh is what build_adjacency accepts, and its motorcycle partition validates.
#include "qsp/submesh.h"

#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_check.h"
#include "qsp/partition.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using qsp::fuzz::finding;
  if (size == 0) return 0;
  const std::uint32_t nv = 1 + data[0] % 64;
  std::vector<std::uint32_t> offsets{0}, corners;
  for (std::size_t i = 1; i < size;) {
    const std::uint32_t degree = 1 + data[i++] % 9;
    for (std::uint32_t k = 0; k < degree && i < size; ++k) corners.push_back(data[i++] % (nv + 2));
    offsets.push_back(static_cast<std::uint32_t>(corners.size()));
  }
  qsp::QuadSubmesh s;
  try {
    s = qsp::quad_submesh(offsets, corners, nv);
  } catch (const qsp::Error& e) {
    qsp::fuzz::check_error(e, "quad_submesh");
    if (e.code() != qsp::ErrorCode::kBadIndex && e.code() != qsp::ErrorCode::kDegenerateFace)
      finding(std::string("quad_submesh refused a mesh: ") + e.what());
    return 0;
  }
  if (s.corner_vertex.size() != corners.size()) finding("corner_vertex has the wrong size");
  for (std::size_t c = 0; c < corners.size(); ++c)
    if (s.vertex_original[s.corner_vertex[c]] != corners[c]) finding("a corner does not glue back");
  std::vector<int> seen(offsets.size() - 1, 0);
  for (std::size_t q = 0; q < s.quad_face.size(); ++q) {
    const std::uint32_t f = s.quad_face[q];
    if (offsets[f + 1] - offsets[f] != 4) finding("a non-quad in the quad submesh");
    ++seen[f];
    for (int k = 0; k < 4; ++k)
      if (s.mesh.quads[4 * q + k] != s.corner_vertex[offsets[f] + k]) finding("a quad's corners moved");
  }
  for (const auto& r : s.regions)
    for (std::uint32_t f : r.faces) ++seen[f];
  for (int n : seen)
    if (n != 1) finding("a face is not listed exactly once");
  try {
    const qsp::Partition p = qsp::partition_motorcycle(s.adjacency);
    for (const auto& part : p.components) {
      const std::string why = qsp::validate(part, &s.adjacency);
      if (!why.empty()) finding("invalid partition: " + why);
    }
  } catch (const qsp::Error& e) {
    finding(std::string("partition of the quad submesh failed: ") + e.what());
  }
  return 0;
}
