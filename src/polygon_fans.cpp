// A polygon mesh's glued edges (counting sorts by endpoint) and vertex fans (one walk per fan), in
// O(corners + vertices): rules 1-4 of qsp/submesh.h.
#include "polygon_fans.h"

#include <algorithm>
#include <string>

#include "qsp/error.h"
#include "qsp/mesh.h"
#include "qsp/submesh.h"

namespace qsp::detail {
namespace {

[[noreturn]] void fail(ErrorCode code, const std::string& message, std::int64_t face = -1) {
  throw Error(code, message, face);
}

std::string face_str(std::uint64_t f) { return "face " + std::to_string(f); }

}  // namespace

PolygonFans polygon_fans(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> corners,
                         std::uint32_t nv) {
  if (std::uint64_t{corners.size()} + nv >= kPolygonSizeLimit)
    fail(ErrorCode::kLimit, "mesh too large: corners plus vertices must stay below 2^31");
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != corners.size())
    fail(ErrorCode::kInternal, "face offsets do not span the corners");
  const auto n = static_cast<std::uint32_t>(corners.size());
  const std::size_t nf = offsets.size() - 1;
  PolygonFans out;

  // Validation, in build_adjacency's order and words: per corner its range, then a repeat in its face.
  out.face_of.resize(n);
  std::vector<std::uint32_t> dest(n);    // per corner: the vertex its half-edge runs to
  std::vector<std::uint8_t> in_quad(n);  // per corner: 1 in a quad
  {
    std::vector<std::uint32_t> seen_in(nv, kInvalid);  // per vertex: the last face it was seen in
    for (std::size_t f = 0; f < nf; ++f) {
      const std::uint32_t b = offsets[f], e = offsets[f + 1];
      if (e < b || e > n) fail(ErrorCode::kInternal, "face offsets decrease at " + face_str(f));
      if (e - b < 3)
        fail(ErrorCode::kDegenerateFace,
             face_str(f) + " has " + std::to_string(e - b) + " corners (a face needs at least 3)",
             static_cast<std::int64_t>(f));
      for (std::uint32_t c = b; c < e; ++c) {
        const std::uint32_t v = corners[c];
        if (v >= nv)
          fail(ErrorCode::kBadIndex,
               face_str(f) + ": vertex index " + std::to_string(v) + " out of range (" + std::to_string(nv) +
                   " vertices)",
               static_cast<std::int64_t>(f));
        if (seen_in[v] == f)
          fail(ErrorCode::kDegenerateFace, face_str(f) + ": vertex " + std::to_string(v) + " appears twice",
               static_cast<std::int64_t>(f));
        seen_in[v] = static_cast<std::uint32_t>(f);
        out.face_of[c] = static_cast<std::uint32_t>(f);
        dest[c] = corners[c + 1 < e ? c + 1 : b];
        in_quad[c] = e - b == 4;
      }
    }
  }
  const auto& face_of = out.face_of;
  auto next = [&](std::uint32_t c) {
    const std::uint32_t f = face_of[c];
    return c + 1 == offsets[f + 1] ? offsets[f] : c + 1;
  };
  auto prev = [&](std::uint32_t c) {
    const std::uint32_t f = face_of[c];
    return c == offsets[f] ? offsets[f + 1] - 1 : c - 1;
  };
  auto lo = [&](std::uint32_t c) { return std::min(corners[c], dest[c]); };
  auto hi = [&](std::uint32_t c) { return std::max(corners[c], dest[c]); };
  auto quad = [&](std::uint32_t c) { return in_quad[c] != 0; };

  // Rule 1. Half-edges in (lo, hi) order by two counting sorts (linear, whatever the valences), so the
  // half-edges of one edge are adjacent.
  std::vector<std::uint32_t> sorted(n);
  {
    std::vector<std::uint32_t> by_hi(n), start(std::size_t{nv} + 1);
    for (std::uint32_t c = 0; c < n; ++c) ++start[hi(c) + 1];
    for (std::uint32_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    for (std::uint32_t c = 0; c < n; ++c) by_hi[start[hi(c)]++] = c;
    std::fill(start.begin(), start.end(), 0);
    for (std::uint32_t c = 0; c < n; ++c) ++start[lo(c) + 1];
    for (std::uint32_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    for (std::uint32_t c : by_hi) sorted[start[lo(c)]++] = c;
  }
  out.twin.assign(n, kInvalid);
  for (std::uint32_t i = 0; i < n;) {
    const std::uint32_t a = lo(sorted[i]), z = hi(sorted[i]);
    std::uint32_t j = i + 1;
    while (j < n && lo(sorted[j]) == a && hi(sorted[j]) == z) ++j;
    if (j - i == 2 && corners[sorted[i]] != corners[sorted[i + 1]]) {
      out.twin[sorted[i]] = sorted[i + 1];
      out.twin[sorted[i + 1]] = sorted[i];
    } else if (j - i >= 2) {
      ++out.cut_edges;  // 3+ faces, or two traversing it the same way: each keeps its own copy
    }
    i = j;
  }
  sorted = {};
  dest = {};

  // Rules 2-4, one fan at a time. ccw(c) is the corner after c counter-clockwise around its vertex
  // (across the edge entering c), cw(c) the one before (across the edge leaving c).
  const auto& twin = out.twin;
  auto ccw = [&](std::uint32_t c) { return twin[prev(c)]; };
  auto cw = [&](std::uint32_t c) { return twin[c] == kInvalid ? kInvalid : next(twin[c]); };
  out.corner_fan.assign(n, kInvalid);
  out.corner_qfan.assign(n, kInvalid);
  out.corner_qfan_other.assign(n, kInvalid);
  std::vector<std::uint32_t> fan;  // the fan's corners counter-clockwise from its clockwise end
  for (std::uint32_t c0 = 0; c0 < n; ++c0) {
    if (out.corner_fan[c0] != kInvalid) continue;
    // cw is injective (next after an involution), so walking it from c0 ends or comes back to c0.
    std::uint32_t s = c0;
    bool closed = false;
    for (std::uint32_t p = cw(s); p != kInvalid; p = cw(s)) {
      if (p == c0) {
        closed = true;
        break;
      }
      s = p;
    }
    fan.clear();
    std::uint32_t c = s, quads = 0;
    do {
      fan.push_back(c);
      if (quad(c)) ++quads;
      c = ccw(c);
    } while (c != kInvalid && c != s);
    const auto id = static_cast<std::uint32_t>(out.fan_vertex.size());
    for (std::uint32_t x : fan) out.corner_fan[x] = id;
    out.fan_vertex.push_back(corners[s]);
    out.fan_quad.push_back(quads > 0 ? 1 : 0);
    if (quads == 0) continue;  // a region's interior vertex
    auto new_qfan = [&] {
      out.qfan_vertex.push_back(corners[s]);
      return static_cast<std::uint32_t>(out.qfan_vertex.size() - 1);
    };
    const auto m = static_cast<std::uint32_t>(fan.size());
    if (quads == m) {
      const std::uint32_t q = new_qfan();
      for (std::uint32_t x : fan) out.corner_qfan[x] = q;
      continue;
    }
    // Runs of quads are the quad fans. A closed fan is read from just after a non-quad corner, so no
    // run wraps around.
    std::uint32_t start = 0;
    if (closed)
      while (quad(fan[start++])) {
      }
    auto at = [&](std::uint32_t t) { return fan[(start + t) % m]; };
    std::uint32_t first_q = kInvalid, last_q = kInvalid;
    for (std::uint32_t t = 0; t < m; ++t) {
      const std::uint32_t x = at(t);
      if (!quad(x)) continue;
      const std::uint32_t p = t > 0 ? at(t - 1) : kInvalid;
      last_q = out.corner_qfan[x] = (p != kInvalid && quad(p)) ? out.corner_qfan[p] : new_qfan();
      if (first_q == kInvalid) first_q = last_q;
    }
    // Rule 4: a non-quad corner takes the next quad fan counter-clockwise, else the next clockwise;
    // corner_qfan_other keeps the clockwise one when both exist.
    std::uint32_t q = closed ? first_q : kInvalid;
    for (std::uint32_t t = m; t-- > 0;) {
      const std::uint32_t x = at(t);
      if (quad(x))
        q = out.corner_qfan[x];
      else
        out.corner_qfan[x] = q;
    }
    q = closed ? last_q : kInvalid;
    for (std::uint32_t t = 0; t < m; ++t) {
      const std::uint32_t x = at(t);
      if (quad(x)) {
        q = out.corner_qfan[x];
      } else if (out.corner_qfan[x] == kInvalid) {
        out.corner_qfan[x] = q;
      } else {
        out.corner_qfan_other[x] = q;
      }
    }
  }
  return out;
}

}  // namespace qsp::detail
