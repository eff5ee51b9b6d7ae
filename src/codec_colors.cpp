// The colours section (format 3.8; format-spec/qsp_format.md, "Colours section"): vertex colours in
// output vertex order, each predicted by the mean of its decoded neighbours, then face colours in output
// face order, each predicted by the last decoded face sharing a vertex; exactly (decimal grids or float
// bits) or on binary grids. The encoder and the decoder run one walk over the mesh (walk_colors), so
// their predictions cannot drift apart.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "entropy.h"
#include "qsp/error.h"
#include "value_domain.h"

namespace qsp {
namespace {

constexpr std::uint8_t kVertexMask = 0x07, kFaceShift = 3, kFaceMask = 0x38, kParallelogramBit = 0x40,
                       kReservedBits = 0x80;
constexpr unsigned kMaxNeighbours = 8;
// Every component costs at least one decision and none less than log2(65536 / 65465) bits: at most ~5116
// a byte.
constexpr std::uint64_t kMaxValuesPerByte = 8192;
constexpr const char* kSection = "colours section";

bool valid_vertex_components(unsigned k) { return k == 0 || k == 3 || k == 4; }
bool valid_face_components(unsigned k) { return k == 0 || k == 1 || k == 3 || k == 4; }

// Per vertex, its corners in corner order, each as the vertices of the next corner, and in a quad of the
// previous and the opposite one (kInvalid in other faces): what the predictions may use.
struct Neighbours {
  std::vector<std::uint32_t> start, next, previous, opposite;
  Neighbours(std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> corner_vertices,
             std::uint32_t vertex_count)
      : start(std::size_t{vertex_count} + 1, 0),
        next(corner_vertices.size()),
        previous(corner_vertices.size(), kInvalid),
        opposite(corner_vertices.size(), kInvalid) {
    for (std::uint32_t v : corner_vertices) ++start[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f + 1 < face_offsets.size(); ++f) {
      const std::uint32_t b = face_offsets[f], e = face_offsets[f + 1];
      for (std::uint32_t k = b; k < e; ++k) {
        const std::uint32_t at = fill[corner_vertices[k]]++;
        next[at] = corner_vertices[k + 1 == e ? b : k + 1];
        if (e - b != 4) continue;
        previous[at] = corner_vertices[b + (k - b + 3) % 4];
        opposite[at] = corner_vertices[b + (k - b + 2) % 4];
      }
    }
  }
};

struct Models {
  std::vector<IntModel> vertex,
      face;  // vertex[4 j + min(n, 2)] or [4 j + 3] (parallelograms), face[2 j + (no neighbour)]
};

// The section's walk: `code(model, prediction, vertex?, component)` returns the integer of the next
// component (the encoder codes its own, the decoder decodes one), stored in `vertex_integers` and
// `face_integers` to predict from.
template <class Code>
void walk_colors(std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> corner_vertices,
                 std::uint32_t vertex_count, unsigned Kv, unsigned Kf, bool parallelograms,
                 std::span<const Domain> domains, std::vector<std::int64_t>& vertex_integers,
                 std::vector<std::int64_t>& face_integers, Code&& code) {
  Models m;
  m.vertex.resize(4 * std::size_t{Kv});
  m.face.resize(2 * std::size_t{Kf});
  if (Kv) {
    const Neighbours around(face_offsets, corner_vertices, vertex_count);
    for (std::uint32_t v = 0; v < vertex_count; ++v) {
      const auto at = [&](std::uint32_t u, unsigned j) { return vertex_integers[std::size_t{u} * Kv + j]; };
      // The quads' parallelograms across v (decoded corners only), else the decoded neighbours' mean.
      std::array<std::int64_t, 4> sum{};
      unsigned n = 0, parallelogram = 0;
      for (std::uint32_t e = around.start[v]; e < around.start[v + 1] && parallelograms && n < kMaxNeighbours;
           ++e) {
        const std::uint32_t a = around.previous[e], b = around.next[e], o = around.opposite[e];
        if (a == kInvalid || a >= v || b >= v || o >= v) continue;
        for (unsigned j = 0; j < Kv; ++j) sum[j] += at(a, j) + at(b, j) - at(o, j);
        ++n;
      }
      if (n) {
        parallelogram = 1;
      } else {
        for (std::uint32_t e = around.start[v]; e < around.start[v + 1] && n < kMaxNeighbours; ++e) {
          const std::uint32_t u = around.next[e];
          if (u >= v) continue;
          for (unsigned j = 0; j < Kv; ++j) sum[j] += at(u, j);
          ++n;
        }
      }
      for (unsigned j = 0; j < Kv; ++j) {
        const std::int64_t p = n   ? domains[j].clamp(floor_div(2 * sum[j] + n, 2 * std::int64_t{n}))
                               : v ? at(v - 1, j)
                                   : domains[j].none();
        vertex_integers[std::size_t{v} * Kv + j] =
            code(m.vertex[4 * j + (parallelogram ? 3 : std::min(n, 2u))], p, domains[j]);
      }
    }
  }
  if (Kf && !face_offsets.empty()) {
    const std::size_t nf = face_offsets.size() - 1;
    std::vector<std::uint32_t> last(vertex_count, kInvalid);
    for (std::size_t g = 0; g < nf; ++g) {
      std::uint32_t h = kInvalid;
      for (std::uint32_t k = face_offsets[g]; k < face_offsets[g + 1]; ++k) {
        const std::uint32_t l = last[corner_vertices[k]];
        if (l != kInvalid && (h == kInvalid || l > h)) h = l;
      }
      for (unsigned j = 0; j < Kf; ++j) {
        const Domain& d = domains[Kv + j];
        const std::int64_t p = h != kInvalid ? face_integers[std::size_t{h} * Kf + j]
                               : g           ? face_integers[(g - 1) * Kf + j]
                                             : d.none();
        face_integers[g * Kf + j] = code(m.face[2 * j + (h == kInvalid)], p, d);
      }
      for (std::uint32_t k = face_offsets[g]; k < face_offsets[g + 1]; ++k)
        last[corner_vertices[k]] = static_cast<std::uint32_t>(g);
    }
  }
}

}  // namespace

std::string encode_colors_section(std::span<const std::uint32_t> face_offsets,
                                  std::span<const std::uint32_t> corner_vertices, std::uint32_t vertex_count,
                                  std::uint8_t vertex_components, std::span<const float> vertex_colors,
                                  std::uint8_t face_components, std::span<const float> face_colors,
                                  std::uint32_t quantize_bits) {
  const unsigned Kv = vertex_components, Kf = face_components;
  const std::size_t nf = face_offsets.empty() ? 0 : face_offsets.size() - 1;
  if (!valid_vertex_components(Kv) || !valid_face_components(Kf) || (Kv == 0 && Kf == 0))
    throw Error(ErrorCode::kUsage, "encode: colours have " + std::to_string(Kv) + " vertex and " +
                                       std::to_string(Kf) + " face components");
  if (vertex_colors.size() != std::size_t{Kv} * vertex_count || face_colors.size() != Kf * nf)
    throw Error(ErrorCode::kUsage, "encode: colour arrays disagree with the vertex and face counts");
  if (quantize_bits > kMaxGridBits)
    throw Error(ErrorCode::kUsage, "--quantize-color takes 1 to " + std::to_string(kMaxGridBits) + " bits");
  std::vector<float> vertex(vertex_colors.begin(), vertex_colors.end()),
      face(face_colors.begin(), face_colors.end());
  for (const std::vector<float>* values : {&vertex, &face})
    for (std::size_t i = 0; i < values->size(); ++i)
      if (!std::isfinite((*values)[i]))
        throw Error(ErrorCode::kBadNumber, std::string(values == &vertex ? "vertex" : "face") + " colour " +
                                               std::to_string(i / (values == &vertex ? Kv : Kf)) +
                                               " is not finite");
  std::vector<Domain> domains(Kv + Kf);
  for (unsigned c = 0; c < Kv + Kf; ++c) {
    std::vector<float>& values = c < Kv ? vertex : face;
    const unsigned K = c < Kv ? Kv : Kf, j = c < Kv ? c : c - Kv;
    // A component exactly on a decimal grid at least as coarse as the binary one asked for (PLY bytes at
    // any BITS) stays there: exact, and no larger.
    const std::uint8_t exact = choose_mode(values, K, j);
    const bool coarser =
        exact != kModeFloat && kPow10[exact - 1u] <= std::ldexp(1.0, static_cast<int>(quantize_bits));
    domains[c].mode = quantize_bits && !coarser && quantize(values, K, j, quantize_bits)
                          ? static_cast<std::uint8_t>(kModeGrid + quantize_bits)
                          : exact;
  }
  // The section with the vertices' neighbour means, and with the quads' parallelograms (smooth colours
  // gain, noisy ones lose): the smaller, the first on a tie.
  const auto section = [&](bool parallelograms) {
    std::vector<std::int64_t> vertex_integers(vertex.size()), face_integers(face.size());
    std::string stream;
    RangeEncoder enc(stream);
    std::size_t at_vertex = 0, at_face = 0;
    walk_colors(face_offsets, corner_vertices, vertex_count, Kv, Kf, parallelograms, domains, vertex_integers,
                face_integers, [&](IntModel& model, std::int64_t prediction, const Domain& d) {
                  const bool is_vertex = at_vertex < vertex.size();
                  const float x = is_vertex ? vertex[at_vertex++] : face[at_face++];
                  const std::int64_t n = d.integer(x);
                  encode_residual(enc, model, n - prediction);
                  return n;
                });
    enc.finish();
    std::string out;
    put_u8(out,
           static_cast<std::uint8_t>(Kv | (Kf << kFaceShift) | (parallelograms ? kParallelogramBit : 0)));
    for (const Domain& d : domains) put_u8(out, d.mode);
    return out + stream;
  };
  std::string best = section(false);
  if (Kv)
    if (std::string other = section(true); other.size() < best.size()) best = std::move(other);
  return best;
}

DecodedColors decode_colors_section(std::string_view payload, std::uint64_t base_offset,
                                    std::span<const std::uint32_t> face_offsets,
                                    std::span<const std::uint32_t> corner_vertices,
                                    std::uint32_t vertex_count) {
  ByteReader in(payload, base_offset, kSection);
  std::uint64_t at = in.offset();
  const std::uint8_t flags = in.u8("flags");
  const unsigned Kv = flags & kVertexMask, Kf = (flags & kFaceMask) >> kFaceShift;
  if (flags & kReservedBits) in.fail_at("reserved flag bits are set (must be zero)", at);
  if (!valid_vertex_components(Kv))
    in.fail_at(std::to_string(Kv) + " components per vertex colour (0, 3 or 4)", at);
  if (!valid_face_components(Kf))
    in.fail_at(std::to_string(Kf) + " components per face colour (0, 1, 3 or 4)", at);
  if (Kv == 0 && Kf == 0) in.fail_at("neither vertex nor face colours", at);
  if ((flags & kParallelogramBit) && Kv == 0) in.fail_at("parallelograms without vertex colours", at);
  std::vector<Domain> domains(Kv + Kf);
  for (Domain& d : domains) {
    at = in.offset();
    d.mode = in.u8("component mode");
    if (!valid_mode(d.mode))
      in.fail_at("component mode " + std::to_string(d.mode) + " (0 to 10, or 17 to 40)", at);
  }
  const std::size_t nf = face_offsets.empty() ? 0 : face_offsets.size() - 1;
  const std::uint64_t values = std::uint64_t{Kv} * vertex_count + std::uint64_t{Kf} * nf;
  // Every component costs at least one decision, and no decision less than log2(65536 / 65465) bits.
  if (values > kMaxValuesPerByte * (in.left() + 8))
    in.fail_at(std::to_string(values) + " colour components cannot fit in the " + std::to_string(in.left()) +
                   " bytes left",
               in.offset());
  const std::uint64_t stream_offset = in.offset();
  RangeDecoder dec(payload.substr(in.pos()), stream_offset, kSection);
  DecodedColors out;
  out.vertex_components = static_cast<std::uint8_t>(Kv);
  out.face_components = static_cast<std::uint8_t>(Kf);
  out.vertex.resize(std::size_t{Kv} * vertex_count);
  out.face.resize(Kf * nf);
  std::vector<std::int64_t> vertex_integers(out.vertex.size()), face_integers(out.face.size());
  std::size_t at_vertex = 0, at_face = 0;
  walk_colors(face_offsets, corner_vertices, vertex_count, Kv, Kf, (flags & kParallelogramBit) != 0, domains,
              vertex_integers, face_integers, [&](IntModel& model, std::int64_t prediction, const Domain& d) {
                const bool is_vertex = at_vertex < out.vertex.size();
                const std::int64_t n = prediction + decode_residual(dec, model);
                const auto fail = [&](const char* what) {
                  const std::size_t i = is_vertex ? at_vertex / Kv : at_face / Kf;
                  throw Error(ErrorCode::kFormat, std::string(kSection) + ": " +
                                                      (is_vertex ? "vertex" : "face") + " colour " +
                                                      std::to_string(i) + what + " (near byte offset " +
                                                      std::to_string(dec.offset()) + ")");
                };
                if (!d.holds(n))
                  fail(d.mode == kModeFloat ? " is a float image outside 32 bits"
                                            : " is an integer outside (-2^40, 2^40)");
                const float x = d.value(n);
                if (!std::isfinite(x)) fail(" is not finite");
                (is_vertex ? out.vertex[at_vertex++] : out.face[at_face++]) = x;
                return n;
              });
  dec.finish();
  return out;
}

}  // namespace qsp
