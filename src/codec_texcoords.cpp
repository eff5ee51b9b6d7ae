// The texture coordinates section (format 3.2; format-spec/qsp_format.md, "Texture coordinates
// section"): which value each corner names, as the corners first name them (new, one its vertex has
// named, none, or an earlier one), then the values predicted from their creating corner's face (the
// parallelogram, corrected by the quads across or fitted to the face's 3D corners; a grid line), exactly
// (decimal grids or float bits) or on binary grids, then with --keep-order the input numbering. From 3.16
// (flag bit 7) a corner's symbol also reads the faces across its edges (is the edge a seam there?) and a
// residual's model the size of the residuals its prediction read. Normals
// (the normals section, same coder) may be predicted from the faces naming them, and octahedral.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "entropy.h"
#include "geometry_values.h"
#include "normal_prediction.h"
#include "permutation_coder.h"
#include "qsp/error.h"
#include "value_domain.h"

namespace qsp {
namespace {

constexpr std::uint8_t kComponentsMask = 0x03, kOrderBit = 0x04, kCorrectionBit = 0x08, kShapeBit = 0x10,
                       kReservedBits = 0xE0;
// Normals only (format 3.10): predicted from the faces naming them; octahedral.
constexpr std::uint8_t kGeometryBit = 0x20, kOctahedralBit = 0x40;
// Texture coordinates only (format 3.16): hints from the faces across, and residuals by activity.
constexpr std::uint8_t kHintBit = 0x80;
// Texture coordinates only (format 3.18): values predicted from their mirror images' (symmetry section).
constexpr std::uint8_t kMirrorBit = 0x20;
constexpr unsigned kContexts = 8, kGeometryContext = 5, kSeamContext = 6, kMirrorContext = 7, kBuckets = 4;
constexpr std::uint32_t kMinOctahedralBits = 2;
// Every value costs at least one decision and none less than log2(65536 / 65465) bits: at most ~5116 a
// byte (8192 leaves room; 2048, before 3.8, refused files of one repeated value that the encoder wrote).
constexpr std::uint64_t kMaxValuesPerByte = 8192;

[[noreturn]] void internal(const std::string& what) { throw Error(ErrorCode::kInternal, "encode: " + what); }
[[noreturn]] void format_error(const CornerValueWords& w, const std::string& what, std::uint64_t offset) {
  throw Error(ErrorCode::kFormat,
              std::string(w.section) + ": " + what + " (near byte offset " + std::to_string(offset) + ")");
}

// Per vertex, the values its corners have named, in one slot per corner (S(v) in the spec).
struct Named {
  std::vector<std::uint32_t> start, size, slots;
  Named(std::span<const std::uint32_t> corner_vertices, std::uint32_t vertex_count)
      : start(std::size_t{vertex_count} + 1, 0), size(vertex_count, 0), slots(corner_vertices.size()) {
    for (std::uint32_t v : corner_vertices) ++start[v + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
  }
  std::span<const std::uint32_t> of(std::uint32_t v) const { return {slots.data() + start[v], size[v]}; }
  void add(std::uint32_t v, std::uint32_t value) { slots[start[v] + size[v]++] = value; }
};

// The decisions and models of the corner symbols. Context: how many values the corner's vertex has
// named (0, 1, 2 or more) and whether an earlier corner of its face crossed a seam (took a value other
// than its vertex's first, new or not): faces beyond a seam name second values.
// With bit 7 also by the hint's state h (below): is_hint[s], then is_new and is_seen[s + 6h], pick[e + 2
// min(h, 1)].
struct SymbolModels {
  std::array<BitModel, 6> is_hint{};
  std::array<BitModel, 18> is_new{}, is_seen{};
  BitModel is_none{};
  IntModel pick[4], far;
};

// A prediction: (sum of weight * value) / 2 over up to 8 terms, or a parallelogram plus half of that sum,
// and its context.
struct Prediction {
  int context = 2;
  int count = 0;
  std::array<std::uint32_t, 8> value{};
  std::array<int, 8> weight{};  // twice the weight
  void add(std::uint32_t v, int w) { value[count] = v, weight[count++] = w; }
  // The shaped parallelogram o + alpha (a - o) + beta (b - o), before the terms' half, if `shaped`.
  bool shaped = false;
  std::uint32_t a = kInvalid, b = kInvalid, o = kInvalid;
  double alpha = 1, beta = 1;
};

// The corner positions, 3 per vertex, for the parallelogram's shape.
struct Shape {
  std::span<const float> positions;
  std::span<const std::uint32_t> corner_vertices;
  double at(std::uint32_t corner, int k) const {
    return static_cast<double>(
        positions[3 * std::size_t{corner_vertices[corner]} + static_cast<unsigned>(k)]);
  }
  // alpha, beta with c - o = alpha (a - o) + beta (b - o) in 3D by least squares (corners' positions),
  // or 1, 1 where that is ill-posed or far from a parallelogram. Every step rounded (no fused multiply-add:
  // this file is compiled with -ffp-contract=off), so every decoder computes the same bits.
  void fit(std::uint32_t a, std::uint32_t b, std::uint32_t o, std::uint32_t c, Prediction& p, double alpha0,
           double beta0) const {
    double ea[3], eb[3], ec[3];
    for (int k = 0; k < 3; ++k) {
      ea[k] = at(a, k) - at(o, k);
      eb[k] = at(b, k) - at(o, k);
      ec[k] = at(c, k) - at(o, k);
    }
    const auto dot = [](const double* x, const double* y) {
      return (x[0] * y[0] + x[1] * y[1]) + x[2] * y[2];
    };
    const double aa = dot(ea, ea), bb = dot(eb, eb), ab = dot(ea, eb), ac = dot(ea, ec), bc = dot(eb, ec);
    const double det = aa * bb - ab * ab;
    p.alpha = alpha0, p.beta = beta0;
    if (!(det > 0x1p-40 * (aa * bb))) return;
    const double alpha = (ac * bb - bc * ab) / det, beta = (bc * aa - ac * ab) / det;
    if (std::fabs(alpha) <= 4 && std::fabs(beta) <= 4) p.alpha = alpha, p.beta = beta;
  }
};

// Where each texture-coordinate edge lies: the first corner k (in output order) whose face runs from
// names[k] to the next corner's name. Per value x, its edges x -> y in corner order: a value is named by
// a handful of corners, so a scan of its few edges finds one; a value (or vertex) with more has its edges
// sorted by (y, k), searched by halves, or a fan of 100,000 triangles would take 10^10 steps.
struct Edges {
  std::vector<std::uint32_t> start;                         // per value and one more: its first edge
  std::vector<std::pair<std::uint32_t, std::uint32_t>> to;  // per edge: (y, corner k)
  Edges(std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> names, std::size_t count)
      : start(count + 1, 0) {
    auto each = [&](auto&& f) {
      for (std::size_t g = 0; g + 1 < face_offsets.size(); ++g) {
        const std::uint32_t first = face_offsets[g], d = face_offsets[g + 1] - first;
        for (std::uint32_t k = 0; k < d; ++k) {
          // (No `% d`: a division per corner costs more than the rest of this loop.)
          const std::uint32_t x = names[first + k], y = names[k + 1 < d ? first + k + 1 : first];
          if (x != kInvalid && y != kInvalid) f(x, y, first + k);
        }
      }
    };
    each([&](std::uint32_t x, std::uint32_t, std::uint32_t) { ++start[x + 1]; });
    std::partial_sum(start.begin(), start.end(), start.begin());
    to.resize(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    each([&](std::uint32_t x, std::uint32_t y, std::uint32_t k) { to[fill[x]++] = {y, k}; });
    for (std::size_t x = 0; x < count; ++x)
      if (start[x + 1] - start[x] > kScan) std::sort(to.begin() + start[x], to.begin() + start[x + 1]);
  }
  // The corner that runs from x to y, or kInvalid.
  std::uint32_t find(std::uint32_t x, std::uint32_t y) const {
    if (start[x + 1] - start[x] > kScan) {
      const auto at = std::lower_bound(to.begin() + start[x], to.begin() + start[x + 1],
                                       std::pair<std::uint32_t, std::uint32_t>{y, 0});
      return at != to.begin() + start[x + 1] && at->first == y ? at->second : kInvalid;
    }
    for (std::uint32_t e = start[x]; e < start[x + 1]; ++e)
      if (to[e].first == y) return to[e].second;
    return kInvalid;
  }
  static constexpr std::uint32_t kScan = 16;  // edges scanned in corner order; more are sorted
};

// Bit 7: what the faces across corner c's edges say of its value, from the corners before it (`names`
// kInvalid beyond them). An edge of c's face from the corner before c (or, at its last corner, to its first)
// meets an earlier face at the first corner running the other way (`twins`); if that face names the same
// value at the shared corner, the edge is no seam there and its value at c's vertex is the hint (state 1);
// else state 2 (a seam); no earlier face across, state 0.
struct Hint {
  unsigned state = 0;
  std::uint32_t value = kInvalid;
};
Hint hint_of(std::uint32_t c, std::uint32_t f, std::span<const std::uint32_t> face_offsets,
             std::span<const std::uint32_t> face_of_corner, std::span<const std::uint32_t> corner_vertices,
             std::span<const std::uint32_t> names, const Edges& twins) {
  Hint h;
  const std::uint32_t first = face_offsets[f], last = face_offsets[f + 1] - 1;
  if (c == first) return h;
  const auto next = [&](std::uint32_t k) {
    const std::uint32_t g = face_of_corner[k];
    return k + 1 < face_offsets[g + 1] ? k + 1 : face_offsets[g];
  };
  // The edge from x (named) to y: the twin runs y -> x; the hint is its name at `at` (x's side is `known`).
  const auto across = [&](std::uint32_t from, std::uint32_t to, std::uint32_t known, bool known_second) {
    const std::uint32_t k = twins.find(corner_vertices[from], corner_vertices[to]);
    if (k == kInvalid || face_of_corner[k] >= f) return false;
    const std::uint32_t there = known_second ? next(k) : k, here = known_second ? k : next(k);
    if (names[there] == names[known] && names[here] != kInvalid) {
      h = {1, names[here]};
      return true;
    }
    h.state = 2;
    return false;
  };
  // The edge before c runs from c - 1 to c: its twin from c's vertex to c - 1's.
  if (across(c, c - 1, c - 1, true)) return h;
  // At the last corner, the edge from c to the first: its twin from the first's vertex to c's.
  if (c == last) across(first, c, first, false);
  return h;
}

// Bit 7: the residual models' bucket, by the mean size of the residuals of the values the prediction reads
// (`size`: per value decoded, the sum of its components' |residual|, each at most 2^20).
std::uint32_t residual_size(std::int64_t r) {
  return static_cast<std::uint32_t>(
      std::min<std::uint64_t>(r < 0 ? 0 - static_cast<std::uint64_t>(r) : r, 1 << 20));
}
unsigned bucket_of(std::uint64_t mean) {
  return std::min<unsigned>(static_cast<unsigned>(std::bit_width(mean)), kBuckets - 1);
}
unsigned bucket_of(const Prediction& p, std::span<const std::uint32_t> size) {
  std::uint64_t sum = 0, n = 0;
  if (p.shaped) sum += std::uint64_t{size[p.a]} + size[p.b] + size[p.o], n += 3;
  for (int k = 0; k < p.count; ++k) sum += size[p.value[k]], ++n;
  return n == 0 ? 0 : bucket_of(sum / n);
}

// The prediction of value `i` from its creating corner (kInvalid: none, i >= T - U).
// Bit 7: the faces across, as the hints find them (W in the spec: each vertex's edges in corner order).
struct Twins {
  const Edges* edges;
  std::span<const std::uint32_t> corner_vertices;
};

Prediction predict(std::uint32_t i, std::uint32_t creating, std::span<const std::uint32_t> face_of_corner,
                   std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> names,
                   const Edges& edges, bool corrections, const Shape* shape, const Twins* twins) {
  Prediction p;
  if (creating != kInvalid) {
    auto known = [&](std::uint32_t t) { return t != kInvalid && t < i ? t : kInvalid; };
    // Corner `corner`'s neighbour k steps on in its face.
    auto step = [&](std::uint32_t corner, std::uint32_t k) {
      const std::uint32_t f = face_of_corner[corner], first = face_offsets[f],
                          d = face_offsets[f + 1] - first;
      std::uint32_t at = corner - first + k;  // (no `% d`, a division: k is below d)
      while (at >= d) at -= d;
      return first + at;
    };
    const std::uint32_t f = face_of_corner[creating], d = face_offsets[f + 1] - face_offsets[f];
    const std::uint32_t a = known(names[step(creating, d - 1)]), b = known(names[step(creating, 1)]),
                        o = d >= 4 ? known(names[step(creating, 2)]) : kInvalid;
    // The quad across the edge from x to y of this face (it runs from y to x): its corners at y and x
    // and the two beyond, when all are known, as (y, x, next of x, next of that).
    std::uint32_t k = kInvalid;  // the last quad across: its corner at y
    auto across = [&](std::uint32_t x, std::uint32_t y, std::array<std::uint32_t, 4>& q) {
      k = edges.find(y, x);
      if (k == kInvalid || face_offsets[face_of_corner[k] + 1] - face_offsets[face_of_corner[k]] != 4)
        return false;
      for (std::uint32_t s = 0; s < 4; ++s)
        if ((q[s] = known(names[step(k, s)])) == kInvalid) return false;
      return true;
    };
    std::array<std::uint32_t, 4> q{};
    if (a != kInvalid && b != kInvalid && o != kInvalid) {
      // The parallelogram, corrected by what it missed in the quads across o-a and b-o.
      p.shaped = true, p.a = a, p.b = b, p.o = o;
      if (shape) shape->fit(step(creating, d - 1), step(creating, 1), step(creating, 2), creating, p, 1, 1);
      int corrected = 0;
      std::array<std::uint32_t, 4> r{};
      const bool left = corrections && across(o, a, q), below = corrections && across(b, o, r);
      // Across o -> a (runs a, o, y1, y2): a's parallelogram there is o + y2 - y1, its miss a - (o + y2 -
      // y1). Across b -> o (runs o, b, z1, z2): b's parallelogram there is o + z1 - z2, its miss b - (o + z1
      // - z2).
      const int w = left && below ? 1 : 2;
      if (left) p.add(q[0], w), p.add(q[1], -w), p.add(q[3], -w), p.add(q[2], w), ++corrected;
      if (below) p.add(r[1], w), p.add(r[0], -w), p.add(r[2], -w), p.add(r[3], w), ++corrected;
      p.context = corrected ? 3 : 0;
      return p;
    }
    // One neighbour: continue the grid line through it from the quad across its edge to o. Across o -> a
    // the quad runs a, o, y1, y2 (the line y2 -> a -> here); across b -> o it runs o, b, z1, z2 (z1 -> b).
    for (const bool first : {true, false}) {
      const std::uint32_t n = first ? a : b;
      if (n == kInvalid) continue;
      if (o != kInvalid && (first ? across(o, a, q) : across(b, o, q))) {
        // n + alpha (o - n) + beta (y - n), beta = -1 and alpha = 0 (the line), or fitted to the corners.
        const std::uint32_t y = first ? 3 : 2;
        p.shaped = true, p.o = n, p.a = o, p.b = q[y], p.alpha = 0, p.beta = -1, p.context = 4;
        if (shape)
          shape->fit(step(creating, 2), step(k, y), step(creating, first ? d - 1 : 1), creating, p, 0, -1);
      } else {
        p.add(n, 2), p.context = 1;
        // Bit 7: the edge to n across a seam, its values there carried over: c = n + (c' - n'), where the
        // face across names c' at c's vertex and n' at n's (a chart that starts at a seam).
        if (twins) {
          const std::uint32_t at = first ? step(creating, d - 1) : step(creating, 1);
          const auto& v = twins->corner_vertices;
          const std::uint32_t t =
              first ? twins->edges->find(v[creating], v[at]) : twins->edges->find(v[at], v[creating]);
          if (t != kInvalid) {
            const std::uint32_t here = known(names[first ? t : step(t, 1)]),
                                there = known(names[first ? step(t, 1) : t]);
            if (here != kInvalid && there != kInvalid)
              p.add(here, 2), p.add(there, -2), p.context = kSeamContext;
          }
        }
      }
      return p;
    }
  }
  p.context = 2;
  if (i > 0) p.add(i - 1, 2);
  return p;
}

// The prediction of component c in `domain` (`integers` holds integer() of every value before the one
// predicted).
std::int64_t prediction(const Domain& domain, const Prediction& p, std::span<const float> values,
                        std::span<const std::int64_t> integers, unsigned K, unsigned c) {
  auto value_of = [&](std::uint32_t t) { return values[std::size_t{t} * K + c]; };
  auto integer_of = [&](std::uint32_t t) { return integers[std::size_t{t} * K + c]; };
  if (p.count == 0 && !p.shaped) return domain.none();
  if (domain.mode != kModeFloat) {
    std::int64_t sum = 0;
    for (int k = 0; k < p.count; ++k) sum += p.weight[k] * integer_of(p.value[k]);
    if (!p.shaped) return clamp_decimal(floor_div(sum + 1, 2));
    const std::int64_t qo = integer_of(p.o);
    const double shape = p.alpha * static_cast<double>(integer_of(p.a) - qo) +
                         p.beta * static_cast<double>(integer_of(p.b) - qo);
    const double t = std::floor((static_cast<double>(sum + 2 * qo) / 2 + shape) + 0.5);
    return static_cast<std::int64_t>(
        std::clamp(t, -static_cast<double>(kDecimalLimit - 1), static_cast<double>(kDecimalLimit - 1)));
  }
  double sum = 0;
  for (int k = 0; k < p.count; ++k) sum += p.weight[k] * static_cast<double>(value_of(p.value[k]));
  if (!p.shaped) {
    const auto x = static_cast<float>(sum / 2);
    return float_image(std::isfinite(x) ? x : value_of(p.value[0]));
  }
  const double o = value_of(p.o);
  const auto x = static_cast<float>(((o + p.alpha * (static_cast<double>(value_of(p.a)) - o)) +
                                     p.beta * (static_cast<double>(value_of(p.b)) - o)) +
                                    sum / 2);
  return float_image(std::isfinite(x) ? x : value_of(p.a));
}

// Bit 5: the value named by the corner before value i's creating corner in its face (normals stored per
// corner repeat their face's), or kInvalid.
std::uint32_t copy_source(std::uint32_t creating, std::span<const std::uint32_t> face_of_corner,
                          std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> names) {
  if (creating == kInvalid || creating == face_offsets[face_of_corner[creating]]) return kInvalid;
  return names[creating - 1];
}

std::vector<std::uint32_t> faces_of_corners(std::span<const std::uint32_t> face_offsets) {
  std::vector<std::uint32_t> face(face_offsets.empty() ? 0 : face_offsets.back());
  for (std::size_t f = 0; f + 1 < face_offsets.size(); ++f)
    std::fill(face.begin() + face_offsets[f], face.begin() + face_offsets[f + 1],
              static_cast<std::uint32_t>(f));
  return face;
}

// Bit 5: corner c's mirror image, the corner at the image of c's vertex in the face that holds the image of
// c's edge to its next corner (running the other way: the mirror reverses orientation), or kInvalid.
// `by_vertex`: the corners' edges by vertex (Edges over corner_vertices).
std::uint32_t mirror_corner(std::uint32_t c, std::span<const std::uint32_t> face_of_corner,
                            std::span<const std::uint32_t> face_offsets,
                            std::span<const std::uint32_t> corner_vertices,
                            std::span<const std::uint32_t> mirror, const Edges& by_vertex) {
  const auto next = [&](std::uint32_t k) {
    const std::uint32_t g = face_of_corner[k];
    return k + 1 < face_offsets[g + 1] ? k + 1 : face_offsets[g];
  };
  const std::uint32_t a = mirror[corner_vertices[c]], b = mirror[corner_vertices[next(c)]];
  if (a == kInvalid || b == kInvalid) return kInvalid;
  const std::uint32_t k = by_vertex.find(b, a);  // the image's corner at b, whose next is at a
  return k == kInvalid ? kInvalid : next(k);
}

// Bit 5: the value the mirror image of value i's creating corner names, where decoded before i, or kInvalid.
struct MirrorSources {
  std::span<const std::uint32_t> mirror;  // per vertex its image, kInvalid where none
  const Edges* by_vertex = nullptr;
  std::uint32_t of(std::uint32_t i, std::uint32_t creating, std::span<const std::uint32_t> face_of_corner,
                   std::span<const std::uint32_t> face_offsets,
                   std::span<const std::uint32_t> corner_vertices,
                   std::span<const std::uint32_t> names) const {
    if (creating == kInvalid) return kInvalid;
    const std::uint32_t k =
        mirror_corner(creating, face_of_corner, face_offsets, corner_vertices, mirror, *by_vertex);
    return k != kInvalid && names[k] != kInvalid && names[k] < i ? names[k] : kInvalid;
  }
};

// Bit 5: the prediction of component c from its mirror source's integer m: m or -m (sign bit c), plus the
// offset the last mirrored value left (0 before the first).
struct MirrorState {
  std::uint8_t signs = 0;
  std::array<std::int64_t, 3> offset{};
  std::int64_t predict(const Domain& d, unsigned c, std::int64_t m) const {
    return d.clamp(((signs >> c) & 1 ? -m : m) + offset[c]);
  }
  void update(unsigned c, std::int64_t value, std::int64_t m) {
    offset[c] = value - ((signs >> c) & 1 ? -m : m);
  }
};

}  // namespace

std::string encode_texcoords_section(std::span<const std::uint32_t> face_offsets,
                                     std::span<const std::uint32_t> corner_vertices,
                                     std::uint32_t vertex_count, std::span<const float> positions,
                                     std::uint8_t components, std::span<const float> values,
                                     std::span<const std::uint32_t> corner_texcoords, bool keep_order,
                                     std::uint32_t quantize_bits, const CornerValueWords& w,
                                     std::uint32_t sample, std::span<const std::uint32_t> mirror) {
  const unsigned K = components;
  if (K < 1 || K > 3 || values.size() % K != 0 || corner_texcoords.size() != corner_vertices.size() ||
      positions.size() != 3 * std::size_t{vertex_count} || face_offsets.empty() ||
      face_offsets.back() != corner_vertices.size() || (!mirror.empty() && mirror.size() != vertex_count) ||
      (!mirror.empty() && w.normals))
    internal(std::string(w.one) + " arrays disagree with the mesh");
  for (const std::uint32_t m : mirror)
    if (m != kInvalid && m >= vertex_count) internal("a mirror image out of range");
  const auto T = static_cast<std::uint32_t>(values.size() / K);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw Error(ErrorCode::kBadNumber, std::string(w.one) + " " + std::to_string(i / K) + " is not finite");

  if (quantize_bits > kMaxGridBits || (w.normals && quantize_bits == 1))
    throw Error(ErrorCode::kUsage,
                "encode: " + std::string(w.one) + " quantization bits " + std::to_string(quantize_bits) +
                    (w.normals ? " is not 0 (exact) or 2 to 24" : " is not 0 (exact) to 24"));
  // Octahedral normals need a direction: a normal of zero length keeps them all exact.
  bool octahedral = w.normals && quantize_bits != 0;
  for (std::size_t i = 0; octahedral && i < T; ++i)
    octahedral = values[3 * i] != 0 || values[3 * i + 1] != 0 || values[3 * i + 2] != 0;
  if (w.normals) quantize_bits = octahedral ? quantize_bits : 0;
  // The corner symbols, once: which value each corner names, numbered as the corners first name them.
  struct Symbol {
    std::uint8_t kind;     // 0 new, 1 seen, 2 none, 3 far
    std::uint8_t context;  // s
    std::uint8_t seam;     // e (pick's context)
    std::uint32_t arg;     // seen: j (coded when `coded`), far: n - 1 - m
    bool coded;            // seen: |S(v)| >= 2; none/far: whether is_seen was coded
    std::uint8_t hint;     // bit 7: the hint's state h, where |S(v)| >= 1 (else 0)
    bool hit;              // bit 7: the corner names the hint
  };
  std::vector<Symbol> symbols;
  symbols.reserve(corner_vertices.size());
  std::vector<std::uint32_t> output(T, kInvalid), input;  // input: per output index, its input index
  std::vector<std::uint32_t> names(corner_vertices.size(), kInvalid), creating;
  const std::vector<std::uint32_t> face_of_corner = faces_of_corners(face_offsets);
  std::optional<Edges> twins;  // bit 7's, for texture coordinates
  if (!w.normals) twins.emplace(face_offsets, corner_vertices, vertex_count);
  const Twins across{twins ? &*twins : nullptr, corner_vertices};
  {
    Named named(corner_vertices, vertex_count);
    std::size_t face = 0;
    std::uint8_t seam = 0;
    for (std::size_t c = 0; c < corner_vertices.size(); ++c) {
      while (face_offsets[face] <= c) ++face, seam = 0;
      const std::uint32_t v = corner_vertices[c], t = corner_texcoords[c];
      if (t != kInvalid && t >= T) internal("a corner names " + std::string(w.one) + " " + std::to_string(t));
      const auto seen = named.of(v);
      const auto s = static_cast<std::uint8_t>(2 * std::min<std::size_t>(seen.size(), 2) + seam);
      const Hint hint = seen.empty() || w.normals
                            ? Hint{}
                            : hint_of(static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(face - 1),
                                      face_offsets, face_of_corner, corner_vertices, names, *twins);
      const auto h = static_cast<std::uint8_t>(hint.state);
      const bool hit = hint.state == 1 && t != kInvalid && output[t] == hint.value;
      if (t != kInvalid && output[t] == kInvalid) {
        symbols.push_back({0, s, seam, 0, false, h, false});
        if (!seen.empty()) seam = 1;
        output[t] = static_cast<std::uint32_t>(input.size());
        input.push_back(t);
        creating.push_back(static_cast<std::uint32_t>(c));
        named.add(v, output[t]);
        names[c] = output[t];
        continue;
      }
      const auto at = t == kInvalid ? seen.end() : std::find(seen.begin(), seen.end(), output[t]);
      if (at != seen.end()) {
        symbols.push_back(
            {1, s, seam, static_cast<std::uint32_t>(at - seen.begin()), seen.size() >= 2, h, hit});
        if (at != seen.begin()) seam = 1;
        names[c] = *at;
        continue;
      }
      if (t == kInvalid) {
        symbols.push_back({2, s, seam, 0, !seen.empty(), h, false});
        continue;
      }
      symbols.push_back(
          {3, s, seam, static_cast<std::uint32_t>(input.size() - 1 - output[t]), !seen.empty(), h, false});
      seam = 1;
      named.add(v, output[t]);
      names[c] = output[t];
    }
  }
  // The values no corner names, in the order of their float bits.
  const auto referenced = static_cast<std::uint32_t>(input.size());
  for (std::uint32_t t = 0; t < T; ++t)
    if (output[t] == kInvalid) input.push_back(t);
  std::sort(input.begin() + referenced, input.end(), [&](std::uint32_t x, std::uint32_t y) {
    for (unsigned c = 0; c < K; ++c) {
      const auto bx = std::bit_cast<std::uint32_t>(values[std::size_t{x} * K + c]);
      const auto by = std::bit_cast<std::uint32_t>(values[std::size_t{y} * K + c]);
      if (bx != by) return bx < by;
    }
    return false;
  });
  std::vector<float> ordered(values.size());
  for (std::uint32_t i = 0; i < T; ++i)
    std::copy_n(&values[std::size_t{input[i]} * K], K, &ordered[std::size_t{i} * K]);
  std::array<Domain, 3> domain{};
  for (unsigned c = 0; c < K && !octahedral; ++c)
    domain[c].mode = quantize_bits && quantize(ordered, K, c, quantize_bits)
                         ? static_cast<std::uint8_t>(kModeGrid + quantize_bits)
                         : choose_mode(ordered, K, c);
  std::vector<std::int64_t> integers(ordered.size());
  for (std::size_t k = 0; k < ordered.size(); ++k) integers[k] = domain[k % K].integer(ordered[k]);
  // With bit 5 a grid holds -0 too (exporters write "-0.000000"): the modes and integers of those sections.
  std::array<Domain, 3> signed_domain = domain;
  std::vector<std::int64_t> signed_integers;
  if (w.normals && !octahedral) {
    for (unsigned c = 0; c < K; ++c) signed_domain[c].mode = choose_mode(ordered, K, c, true);
    signed_integers.resize(ordered.size());
    for (std::size_t k = 0; k < ordered.size(); ++k)
      signed_integers[k] = signed_domain[k % K].integer(ordered[k]);
  }
  const Edges edges(face_offsets, names, T);
  const Shape shape{positions, corner_vertices};
  const GeometryNormals geometry =
      w.normals ? geometry_normals(face_offsets, corner_vertices, positions, names, referenced)
                : GeometryNormals{};
  const auto from_geometry = [&](std::uint32_t i) { return i < referenced && geometry.valid[i]; };
  // Bit 5: each value's mirror source, and per component the sign whose offsets change least from one
  // mirrored value to the next (the residuals the last offset leaves).
  const MirrorSources sources{mirror, twins ? &*twins : nullptr};
  std::vector<std::uint32_t> source;
  std::uint8_t signs = 0;
  if (!mirror.empty() && twins) {
    source.assign(T, kInvalid);
    std::size_t found = 0;
    for (std::uint32_t i = 0; i < referenced; ++i)
      found += (source[i] = sources.of(i, creating[i], face_of_corner, face_offsets, corner_vertices,
                                       names)) != kInvalid;
    if (found == 0) source.clear();
    for (unsigned c = 0; c < K && !source.empty(); ++c) {
      std::array<std::uint64_t, 2> cost{};
      for (const unsigned s : {0u, 1u}) {
        std::int64_t last = 0;
        for (std::uint32_t i = 0; i < referenced; ++i) {
          if (source[i] == kInvalid) continue;
          const std::int64_t m = integers[std::size_t{source[i]} * K + c],
                             offset = integers[std::size_t{i} * K + c] - (s ? -m : m);
          cost[s] += residual_size(offset - last);
          last = offset;
        }
      }
      if (cost[1] < cost[0]) signs = static_cast<std::uint8_t>(signs | 1u << c);
    }
  }

  const auto put_symbols = [&](RangeEncoder& enc, bool hints) {
    SymbolModels m;
    for (const Symbol& y : symbols) {
      const unsigned h = hints ? y.hint : 0, x = y.context + 6 * h;
      if (h == 1) {
        enc.encode_bit(m.is_hint[y.context], y.hit);
        if (y.hit) continue;
      }
      enc.encode_bit(m.is_new[x], y.kind == 0);
      if (y.kind == 0) continue;
      if (y.kind == 1 || y.coded) enc.encode_bit(m.is_seen[x], y.kind == 1);
      if (y.kind == 1) {
        if (y.coded) m.pick[y.seam + (h != 0 ? 2 : 0)].encode(enc, y.arg);
        continue;
      }
      enc.encode_bit(m.is_none, y.kind == 2);
      if (y.kind == 3) m.far.encode(enc, y.arg);
    }
  };
  const auto finish = [&](RangeEncoder& enc, std::string& stream, std::uint8_t tools,
                          std::span<const std::uint8_t> modes) {
    if (keep_order) {
      PermutationCoder perm;
      for (std::uint32_t i = 0; i < T; ++i) perm.encode(enc, input[i], T);
    }
    enc.finish();
    std::string out;
    put_u8(out, static_cast<std::uint8_t>(K | (keep_order ? kOrderBit : 0) | tools));
    put_varint(out, T);
    put_varint(out, T - referenced);
    for (const std::uint8_t mode : modes) put_u8(out, mode);
    return out + stream;
  };
  const std::array<Domain, 3>& plain_domain = domain;
  const std::vector<std::int64_t>& plain_integers = integers;
  // The section with one of the prediction tools (flag bits 3 and 4), or neither; normals predicted from
  // the faces where they can be (bit 5). With `period` above 1 only the residuals of one run of 256 values
  // in every `period` (predictions read the input's values, so any may be left out): a stream to compare
  // tools by, over the whole mesh (the symbols before them are the same for every tool).
  const auto section = [&](std::uint8_t tools, std::uint32_t period) {
    std::string stream;
    RangeEncoder enc(stream);
    const bool hints = (tools & kHintBit) != 0;
    if (period == 1) put_symbols(enc, hints);
    std::vector<IntModel> residual(kContexts * K * kBuckets);
    std::vector<std::uint32_t> size(hints ? T : 0, 0);  // bit 7: per value, its residuals' size
    const bool faces = w.normals && (tools & kGeometryBit) != 0;
    const std::array<Domain, 3>& doms = faces ? signed_domain : plain_domain;
    const std::vector<std::int64_t>& ints = faces ? signed_integers : plain_integers;
    std::array<BitModel, 3> minus{};
    // Bit 5: a grid value's sign where its integer is 0.
    const auto sign = [&](std::uint32_t i, unsigned c) {
      if (faces && doms[c].mode != kModeFloat && ints[std::size_t{i} * K + c] == 0)
        enc.encode_bit(minus[c], std::signbit(ordered[std::size_t{i} * K + c]));
    };
    BitModel copy{};
    const bool mirrored = !w.normals && (tools & kMirrorBit) != 0;
    MirrorState state{signs, {}};
    for (std::uint32_t i = 0; i < T; ++i) {
      if (period > 1 && (i >> 8) % period != 0) continue;
      if (mirrored && source[i] != kInvalid) {
        const std::uint32_t m = source[i];
        const unsigned bucket = hints ? bucket_of(size[m]) : 0;
        for (unsigned c = 0; c < K; ++c) {
          const std::int64_t value = ints[std::size_t{i} * K + c], from = ints[std::size_t{m} * K + c];
          const std::int64_t r = value - state.predict(doms[c], c, from);
          encode_residual(enc, residual[kBuckets * (K * kMirrorContext + c) + bucket], r);
          if (hints) size[i] += residual_size(r);
          state.update(c, value, from);
        }
        continue;
      }
      const std::uint32_t j =
          faces && i < referenced ? copy_source(creating[i], face_of_corner, face_offsets, names) : kInvalid;
      if (j != kInvalid) {
        bool same = true;
        for (unsigned c = 0; c < K; ++c)
          same = same && std::bit_cast<std::uint32_t>(ordered[std::size_t{i} * K + c]) ==
                             std::bit_cast<std::uint32_t>(ordered[std::size_t{j} * K + c]);
        enc.encode_bit(copy, same);
        if (same) continue;
      }
      if (faces && from_geometry(i)) {
        for (unsigned c = 0; c < K; ++c) {
          encode_residual(
              enc, residual[kBuckets * (K * kGeometryContext + c)],
              ints[std::size_t{i} * K + c] - doms[c].nearest(geometry.unit[3 * std::size_t{i} + c]));
          sign(i, c);
        }
        continue;
      }
      const Prediction p = predict(i, i < referenced ? creating[i] : kInvalid, face_of_corner, face_offsets,
                                   names, edges, (tools & kCorrectionBit) != 0,
                                   (tools & kShapeBit) ? &shape : nullptr, hints ? &across : nullptr);
      const unsigned bucket = hints ? bucket_of(p, size) : 0;
      for (unsigned c = 0; c < K; ++c) {
        const std::int64_t r = ints[std::size_t{i} * K + c] - prediction(doms[c], p, ordered, ints, K, c);
        encode_residual(enc, residual[kBuckets * (K * p.context + c) + bucket], r);
        if (hints) size[i] += residual_size(r);
        sign(i, c);
      }
    }
    if (period > 1) {
      enc.finish();
      return stream;
    }
    std::array<std::uint8_t, 4> header{};  // the modes, then bit 5's signs
    for (unsigned c = 0; c < K; ++c) header[c] = doms[c].mode;
    header[K] = signs;
    return finish(enc, stream, tools, std::span(header.data(), K + (mirrored ? 1 : 0)));
  };
  // Octahedral normals: each the grid point nearest in angle, coded against its prediction's (from the
  // faces with bit 5, else the normal before), in the hemisphere of the prediction (z mirrored if below).
  const auto octahedral_section = [&](std::uint8_t tools) {
    std::string stream;
    RangeEncoder enc(stream);
    put_symbols(enc, false);
    const Octahedral grid(quantize_bits);
    std::vector<IntModel> residual(4);
    std::array<double, 3> previous{0, 0, 1};
    for (std::uint32_t i = 0; i < T; ++i) {
      const bool faces = (tools & kGeometryBit) && from_geometry(i);
      const std::array<double, 3> p = faces ? geometry.at(i) : previous;
      const bool below = p[2] < 0;
      const std::array<std::int64_t, 2> predicted = grid.nearest(p, below);
      const float* v = &ordered[3 * std::size_t{i}];
      const std::array<std::int64_t, 2> q = grid.best({v[0], v[1], v[2]}, below);
      for (unsigned c = 0; c < 2; ++c)
        encode_residual(enc, residual[2 * (faces ? 0 : 1) + c], q[c] - predicted[c]);
      const std::array<float, 3> n = grid.normal(q[0], q[1], below);
      previous = {n[0], n[1], n[2]};
    }
    const std::uint8_t bits = static_cast<std::uint8_t>(quantize_bits);
    return finish(enc, stream, static_cast<std::uint8_t>(tools | kOctahedralBit), std::span(&bits, 1));
  };
  if (octahedral) {
    std::string with = octahedral_section(kGeometryBit), without = octahedral_section(0);
    return without.size() < with.size() ? without : with;
  }
  // The smallest of the predictions (the first on a tie): the plain parallelogram, corrected by the quads
  // across (smooth layouts), or shaped by the corners' positions (charts that follow the surface's shape
  // rather than the patches); for normals each also with the faces' normals where they exist (3.10), tried
  // last so a file they do not make smaller keeps its 3.5 bytes. With a sample, they are compared on about
  // `sample` values spread over the mesh and only the smallest is coded whole.
  // Texture coordinates also with the hints and buckets (bit 7, 3.16), tried after the rest so a file they
  // do not make smaller keeps its 3.2 bytes; compared on a sample, which leaves the hints' symbols out, they
  // alone are tried: on a mesh that large they save more than the buckets could cost.
  const bool sampled = sample > 0 && T >= 2 * sample;
  std::vector<std::uint8_t> candidates;
  for (const std::uint8_t more : {std::uint8_t{0}, kGeometryBit, kHintBit}) {
    if ((more == kGeometryBit && !w.normals) || (more == kHintBit && w.normals)) continue;
    if (sampled && !w.normals && more != kHintBit) continue;
    for (const std::uint8_t tools : {std::uint8_t{0}, kCorrectionBit, kShapeBit})
      candidates.push_back(static_cast<std::uint8_t>(tools | more));
  }
  if (sampled) {
    const std::uint32_t period = T / sample;
    std::uint8_t chosen = candidates.front();
    std::size_t smallest = std::numeric_limits<std::size_t>::max();
    for (const std::uint8_t tools : candidates)
      if (const std::size_t size = section(tools, period).size(); size < smallest)
        smallest = size, chosen = tools;
    // Bit 5 (3.18) with the tools chosen, where the values have mirror images.
    if (!source.empty() && section(chosen | kMirrorBit, period).size() < smallest)
      chosen = static_cast<std::uint8_t>(chosen | kMirrorBit);
    return section(chosen, 1);
  }
  std::string best;
  std::uint8_t chosen = 0;
  for (const std::uint8_t tools : candidates) {
    std::string bytes = section(tools, 1);
    if (best.empty() || bytes.size() < best.size()) best = std::move(bytes), chosen = tools;
  }
  if (!source.empty())
    if (std::string bytes = section(static_cast<std::uint8_t>(chosen | kMirrorBit), 1);
        bytes.size() < best.size())
      best = std::move(bytes);
  return best;
}

DecodedTexcoords decode_texcoords_section(std::string_view payload, std::uint64_t base_offset,
                                          std::span<const std::uint32_t> face_offsets,
                                          std::span<const std::uint32_t> corner_vertices,
                                          std::uint32_t vertex_count, std::span<const float> positions,
                                          bool order_section, const DecodeLimits& limits,
                                          const CornerValueWords& w, std::uint8_t minor,
                                          std::span<const std::uint32_t> mirror) {
  ByteReader in(payload, base_offset, w.section);
  std::uint64_t at = in.offset();
  const std::uint8_t flags = in.u8("flags");
  const unsigned K = flags & kComponentsMask;
  if (K == 0 || (w.components && K != w.components))
    in.fail_at(std::to_string(K) + " components per " + w.one + " (" +
                   (w.components ? std::to_string(w.components) : std::string("1 to 3")) + ")",
               at);
  const std::uint8_t normal_bits = kGeometryBit | kOctahedralBit;
  if (flags & kReservedBits & ~(w.normals ? normal_bits : kHintBit | kMirrorBit))
    in.fail_at("reserved flag bits are set (must be zero)", at);
  const bool mirrored = !w.normals && (flags & kMirrorBit) != 0;
  const bool faces =
      w.normals && (flags & kGeometryBit) != 0;  // (bit 5 is the mirror's in texture coordinates)
  if (mirrored && minor < kFormatMinorTexcoordMirror)
    in.fail_at("flag bit 5 (mirror prediction) is format 3." + std::to_string(kFormatMinorTexcoordMirror) +
                   "'s, and the file says it is 3." + std::to_string(minor),
               at);
  if (mirrored && mirror.size() != vertex_count)
    in.fail_at("flag bit 5 (mirror prediction) without a symmetry section (or beside a polygons section)",
               at);
  const bool hints = (flags & kHintBit) != 0;
  if (hints && minor < kFormatMinorSeamHints)
    in.fail_at("flag bit 7 (hints from the faces across) is format 3." +
                   std::to_string(kFormatMinorSeamHints) + "'s, and the file says it is 3." +
                   std::to_string(minor),
               at);
  if (w.normals && (flags & normal_bits) && minor < kFormatMinorNormalsGeometry)
    in.fail_at("normals predicted from the faces or octahedral are format 3." +
                   std::to_string(kFormatMinorNormalsGeometry) + "'s, and the file says it is 3." +
                   std::to_string(minor),
               at);
  if ((flags & kCorrectionBit) && (flags & kShapeBit)) in.fail_at("corrections and shapes are both set", at);
  const bool octahedral = (flags & kOctahedralBit) != 0;
  if (octahedral && (flags & (kCorrectionBit | kShapeBit)))
    in.fail_at("octahedral normals with corrections or shapes", at);
  if (((flags & kOrderBit) != 0) != order_section)
    in.fail_at(order_section ? "the order bit is clear beside an order section"
                             : "the order bit is set but the file has no order section",
               at);
  at = in.offset();
  const std::string count_what = std::string(w.one) + " count";
  const std::uint64_t T = in.varint(count_what.c_str());
  if (T > kMaxVertices) in.fail_at(count_what + " exceeds the format's 2^31 - 1", at);
  if (T > limits.*w.limit)
    throw Error(ErrorCode::kLimit, count_what + " " + std::to_string(T) + " exceeds the limit " +
                                       std::to_string(limits.*w.limit) + " (at byte offset " +
                                       std::to_string(at) + ")");
  at = in.offset();
  const std::string unreferenced_what = "unreferenced " + count_what;
  const std::uint64_t U = in.varint(unreferenced_what.c_str());
  if (U > T) in.fail_at(std::string("more unreferenced ") + w.many + " than " + w.many, at);
  if (T - U > corner_vertices.size())
    in.fail_at(std::to_string(T - U) + " referenced " + w.many + " but only " +
                   std::to_string(corner_vertices.size()) + " corners",
               at);
  // Every value costs at least one decision of its residual's model, and no decision less than
  // log2(65536 / 65465) bits: a tiny section declaring millions of values is refused unallocated.
  if (T > kMaxValuesPerByte * (in.left() + 8))
    in.fail_at(
        std::to_string(T) + " " + w.many + " cannot fit in the " + std::to_string(in.left()) + " bytes left",
        at);
  std::array<Domain, 3> domain{};
  std::uint32_t bits = 0;  // octahedral
  if (octahedral) {
    at = in.offset();
    bits = in.u8("octahedral bits");
    if (bits < kMinOctahedralBits || bits > kMaxGridBits)
      in.fail_at("octahedral bits " + std::to_string(bits) + " (2 to 24)", at);
  }
  for (unsigned c = 0; c < K && !octahedral; ++c) {
    at = in.offset();
    domain[c].mode = in.u8("component mode");
    if (!valid_mode(domain[c].mode))
      in.fail_at("component mode " + std::to_string(domain[c].mode) + " (0 to 10, or 17 to 40)", at);
  }
  MirrorState state;
  if (mirrored) {
    at = in.offset();
    state.signs = in.u8("mirror signs");
    if (state.signs >> K) in.fail_at("mirror sign bits beyond the " + std::to_string(K) + " components", at);
  }
  const std::uint64_t stream_offset = in.offset();
  RangeDecoder dec(payload.substr(in.pos()), stream_offset, w.section);

  DecodedTexcoords out;
  out.components = static_cast<std::uint8_t>(K);
  out.corners.assign(corner_vertices.size(), kInvalid);
  std::vector<std::uint32_t> creating;
  creating.reserve(T - U);
  Named named(corner_vertices, vertex_count);
  const std::vector<std::uint32_t> face_of_corner = faces_of_corners(face_offsets);
  std::optional<Edges> twins;
  if (hints || mirrored) twins.emplace(face_offsets, corner_vertices, vertex_count);
  SymbolModels m;
  std::uint32_t n = 0;
  std::size_t face = 0;
  unsigned seam = 0;
  for (std::size_t c = 0; c < corner_vertices.size(); ++c) {
    while (face_offsets[face] <= c) ++face, seam = 0;
    const std::uint32_t v = corner_vertices[c];
    const auto seen = named.of(v);
    const unsigned s = 2 * static_cast<unsigned>(std::min<std::size_t>(seen.size(), 2)) + seam;
    const Hint hint = hints && !seen.empty()
                          ? hint_of(static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(face - 1),
                                    face_offsets, face_of_corner, corner_vertices, out.corners, *twins)
                          : Hint{};
    if (hint.state == 1 && dec.decode_bit(m.is_hint[s])) {
      // The hint is a value of S(v): the first value of a vertex, or a seam crossed.
      if (hint.value != seen[0]) seam = 1;
      out.corners[c] = hint.value;
      continue;
    }
    const unsigned x = s + 6 * hint.state;
    if (dec.decode_bit(m.is_new[x])) {
      if (n >= T - U)
        format_error(w,
                     std::string("more ") + w.many + " named than the " + std::to_string(T - U) + " declared",
                     dec.offset());
      if (!seen.empty()) seam = 1;
      creating.push_back(static_cast<std::uint32_t>(c));
      named.add(v, n);
      out.corners[c] = n++;
      continue;
    }
    if (!seen.empty() && dec.decode_bit(m.is_seen[x])) {
      const std::uint32_t j = seen.size() >= 2 ? m.pick[seam + (hint.state != 0 ? 2 : 0)].decode(dec) : 0;
      if (j >= seen.size())
        format_error(w,
                     "corner " + std::to_string(c) + " picks value " + std::to_string(j) +
                         " of its vertex's " + std::to_string(seen.size()),
                     dec.offset());
      out.corners[c] = seen[j];
      if (j != 0) seam = 1;
      continue;
    }
    if (dec.decode_bit(m.is_none)) continue;
    const std::uint32_t back = m.far.decode(dec);
    if (back >= n)
      format_error(w, "corner " + std::to_string(c) + " names a " + w.one + " before the first",
                   dec.offset());
    out.corners[c] = n - 1 - back;
    named.add(v, out.corners[c]);
    seam = 1;
  }
  if (n != T - U)
    format_error(w,
                 "the corners name " + std::to_string(n) + " " + w.many + ", not the " +
                     std::to_string(T - U) + " declared",
                 dec.offset());

  out.values.resize(T * K);
  std::vector<std::int64_t> integers(T * K);  // integer() of each decoded value, to predict from
  std::vector<IntModel> residual(kContexts * K * kBuckets);
  std::vector<std::uint32_t> size(hints ? T : 0, 0);  // bit 7: per value, its residuals' size
  const Edges edges(face_offsets, out.corners, T);
  const Twins across{hints ? &*twins : nullptr, corner_vertices};
  const MirrorSources sources{mirror, twins ? &*twins : nullptr};
  std::array<BitModel, 3> minus{};  // bit 5: the sign of a grid value whose integer is 0
  BitModel copy{};                  // bit 5: a value the same as the one its face's corner before names
  // Component c of value i from its integer.
  const auto store = [&](std::uint32_t i, unsigned c, std::int64_t value) {
    if (!domain[c].holds(value))
      format_error(
          w,
          domain[c].mode == kModeFloat ? "a float image outside 32 bits" : "an integer outside (-2^40, 2^40)",
          dec.offset());
    float x = domain[c].value(value);
    if (faces && domain[c].mode != kModeFloat && value == 0 && dec.decode_bit(minus[c])) x = -0.0f;
    if (!std::isfinite(x))
      format_error(w, std::string(w.one) + " " + std::to_string(i) + " is not finite", dec.offset());
    out.values[std::size_t{i} * K + c] = x;
    integers[std::size_t{i} * K + c] = domain[c].integer(x);
  };
  const Shape shape{positions, corner_vertices};
  const GeometryNormals geometry =
      faces ? geometry_normals(face_offsets, corner_vertices, positions, out.corners, n) : GeometryNormals{};
  const auto from_geometry = [&](std::uint32_t i) { return faces && i < n && geometry.valid[i]; };
  const Octahedral grid(octahedral ? bits : kMinOctahedralBits);
  std::array<double, 3> previous{0, 0, 1};  // octahedral: the last normal decoded
  for (std::uint32_t i = 0; i < T; ++i) {
    if (octahedral) {
      const bool from_faces = from_geometry(i);
      const std::array<double, 3> p = from_faces ? geometry.at(i) : previous;
      const bool below = p[2] < 0;
      const std::array<std::int64_t, 2> predicted = grid.nearest(p, below);
      std::array<std::int64_t, 2> q{};
      for (unsigned c = 0; c < 2; ++c) {
        q[c] = predicted[c] + decode_residual(dec, residual[2 * (from_faces ? 0 : 1) + c]);
        if (q[c] < -grid.h || q[c] > grid.h)
          format_error(w,
                       "normal " + std::to_string(i) + ": octahedral integer " + std::to_string(q[c]) +
                           " outside [-" + std::to_string(grid.h) + ", " + std::to_string(grid.h) + "]",
                       dec.offset());
      }
      const std::array<float, 3> x = grid.normal(q[0], q[1], below);
      std::copy(x.begin(), x.end(), &out.values[3 * std::size_t{i}]);
      previous = {x[0], x[1], x[2]};
      continue;
    }
    const std::uint32_t j =
        faces && i < n ? copy_source(creating[i], face_of_corner, face_offsets, out.corners) : kInvalid;
    if (j != kInvalid && dec.decode_bit(copy)) {
      for (unsigned c = 0; c < K; ++c) {
        out.values[std::size_t{i} * K + c] = out.values[std::size_t{j} * K + c];
        integers[std::size_t{i} * K + c] = integers[std::size_t{j} * K + c];
      }
      continue;
    }
    if (from_geometry(i)) {
      for (unsigned c = 0; c < K; ++c) {
        const std::int64_t predicted = domain[c].nearest(geometry.unit[3 * std::size_t{i} + c]);
        const std::int64_t value =
            predicted + decode_residual(dec, residual[kBuckets * (K * kGeometryContext + c)]);
        store(i, c, value);
      }
      continue;
    }
    const std::uint32_t from = mirrored ? sources.of(i, i < n ? creating[i] : kInvalid, face_of_corner,
                                                     face_offsets, corner_vertices, out.corners)
                                        : kInvalid;
    if (from != kInvalid) {
      const unsigned bucket = hints ? bucket_of(size[from]) : 0;
      for (unsigned c = 0; c < K; ++c) {
        const std::int64_t source = integers[std::size_t{from} * K + c];
        const std::int64_t r = decode_residual(dec, residual[kBuckets * (K * kMirrorContext + c) + bucket]);
        store(i, c, state.predict(domain[c], c, source) + r);
        if (hints) size[i] += residual_size(r);
        state.update(c, integers[std::size_t{i} * K + c], source);
      }
      continue;
    }
    const Prediction p = predict(i, i < n ? creating[i] : kInvalid, face_of_corner, face_offsets, out.corners,
                                 edges, (flags & kCorrectionBit) != 0, (flags & kShapeBit) ? &shape : nullptr,
                                 hints ? &across : nullptr);
    const unsigned bucket = hints ? bucket_of(p, size) : 0;
    for (unsigned c = 0; c < K; ++c) {
      const std::int64_t predicted = prediction(domain[c], p, out.values, integers, K, c);
      const std::int64_t r = decode_residual(dec, residual[kBuckets * (K * p.context + c) + bucket]);
      store(i, c, predicted + r);
      if (hints) size[i] += residual_size(r);
    }
  }
  if (order_section) {
    // Output value i had input index input[i]: give the values and the corners the input numbering.
    PermutationCoder perm;
    perm.section = w.section;
    std::vector<std::uint8_t> used(T, 0);
    std::vector<std::uint32_t> input(T);
    for (std::uint32_t i = 0; i < T; ++i)
      input[i] = perm.decode(dec, static_cast<std::uint32_t>(T), used, w.one);
    std::vector<float> values(out.values.size());
    for (std::uint32_t i = 0; i < T; ++i)
      std::copy_n(&out.values[std::size_t{i} * K], K, &values[std::size_t{input[i]} * K]);
    out.values = std::move(values);
    for (std::uint32_t& t : out.corners)
      if (t != kInvalid) t = input[t];
  }
  dec.finish();
  return out;
}

}  // namespace qsp
