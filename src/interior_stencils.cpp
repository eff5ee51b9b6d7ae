// The stencils of a polygon mesh's interior vertices where the geometry section codes them (format 3.12,
// format-spec/qsp_format.md "Interior positions section"): each predicted half way across its fan of
// region faces, or from one coded neighbour. Encoder and decoder both build them here.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "codec_sections.h"
#include "qsp/error.h"

namespace qsp {
namespace {

// One face around an interior vertex: the corners before (b) and after (a) it, and the face.
struct Wedge {
  std::uint32_t b, a, face;
};

}  // namespace

InteriorOwners interior_owners(const PolygonFaces& faces, std::uint32_t layout_vertices) {
  InteriorOwners out;
  std::uint32_t owners = 0;
  for (std::uint32_t x = 0; x < faces.ref_vertex.size(); ++x) {
    if (faces.ref_vertex[x] != owners) continue;
    ++owners;
    if (x < layout_vertices) {
      out.layout_owner.push_back(x);
    } else {
      out.interior_refs.push_back(x);
    }
  }
  return out;
}

std::vector<Stencil> interior_stencils(const PolygonFaces& faces, std::uint32_t layout_vertices,
                                       std::span<const std::uint32_t> coding) {
  const InteriorOwners own = interior_owners(faces, layout_vertices);
  const auto nl = static_cast<std::uint32_t>(own.layout_owner.size());
  const auto n = static_cast<std::uint32_t>(own.interior_refs.size());
  if (n == 0) return {};
  // Coding position of each layout vertex (patch order permutes them).
  std::vector<std::uint32_t> position_of;
  if (!coding.empty()) {
    position_of.assign(layout_vertices, kInvalid);
    for (std::uint32_t k = 0; k < coding.size(); ++k) position_of[coding[k]] = k;
  }
  const auto pos = [&](std::uint32_t u) {
    if (u >= nl) return layout_vertices + (u - nl);
    const std::uint32_t x = own.layout_owner[u];
    return position_of.empty() ? x : position_of[x];
  };

  // Every wedge at an interior output vertex, grouped by vertex in face order (one counting pass).
  const std::size_t nf = faces.face_offsets.size() - 1;
  std::vector<std::uint32_t> start(std::size_t{n} + 1, 0);
  for (std::uint32_t c : faces.corners)
    if (c >= nl) {
      if (c - nl >= n) throw Error(ErrorCode::kInternal, "interior stencils: a corner past the vertices");
      ++start[c - nl + 1];
    }
  for (std::uint32_t j = 0; j < n; ++j) start[j + 1] += start[j];
  std::vector<Wedge> wedges(start[n]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::uint32_t b0 = faces.face_offsets[f], d = faces.face_offsets[f + 1] - b0;
    for (std::uint32_t i = 0; i < d; ++i) {
      const std::uint32_t c = faces.corners[b0 + i];
      if (c < nl) continue;
      wedges[fill[c - nl]++] = {faces.corners[b0 + (i + d - 1) % d], faces.corners[b0 + (i + 1) % d],
                                static_cast<std::uint32_t>(f)};
    }
  }

  std::vector<Stencil> out(n);
  std::vector<Wedge> by_b;
  std::vector<std::uint32_t> cursor, fan;
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::span<const Wedge> around(wedges.data() + start[j], start[j + 1] - start[j]);
    if (around.empty()) continue;  // the decoder's rebuild gives every interior vertex a face
    // The wedges sorted by (b, face); a cursor per run of equal b at its first wedge not yet taken.
    by_b.assign(around.begin(), around.end());
    std::sort(by_b.begin(), by_b.end(),
              [](const Wedge& x, const Wedge& y) { return x.b != y.b ? x.b < y.b : x.face < y.face; });
    cursor.resize(by_b.size());
    for (std::size_t i = 0; i < by_b.size(); ++i) cursor[i] = static_cast<std::uint32_t>(i);
    const auto run_of = [&](std::uint32_t b) {
      return static_cast<std::size_t>(
          std::lower_bound(by_b.begin(), by_b.end(), b,
                           [](const Wedge& w, std::uint32_t v) { return w.b < v; }) -
          by_b.begin());
    };
    // The first face in output order is the first of its run: taken.
    fan.assign({around[0].b, around[0].a});
    ++cursor[run_of(around[0].b)];
    bool closed = false;
    for (;;) {
      const std::size_t r = run_of(fan.back());
      if (r == by_b.size() || by_b[r].b != fan.back()) break;
      const std::uint32_t c = cursor[r];
      if (c == by_b.size() || by_b[c].b != fan.back()) break;
      ++cursor[r];
      if (by_b[c].a == fan.front()) {
        closed = true;
        break;
      }
      fan.push_back(by_b[c].a);
    }

    const std::uint32_t k = layout_vertices + j;
    const auto size = static_cast<std::uint32_t>(fan.size());
    std::uint32_t i = 0;
    while (i < size && pos(fan[i]) >= k) ++i;
    if (i == size) continue;  // no coded neighbour: kind 0
    Stencil& s = out[j];
    s.w = pos(fan[i]);
    std::uint32_t across = kInvalid;
    if (closed) {
      across = fan[(i + size / 2) % size];
    } else if (size - 1 > i) {
      across = fan[size - 1];
    }
    if (across != kInvalid && across != fan[i] && pos(across) < k) {
      s.far = pos(across);
      s.far_dist = 1;
    }
  }
  return out;
}

}  // namespace qsp
