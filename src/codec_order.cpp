// The order section (--keep-order): where each original vertex and face went in the canonical order,
// coded as the step from "one after the previous one" (small when the original order runs along the
// same rows as the canonical one), plus each face's corner rotation. See qsp_format.md, "Order section".
#include <array>
#include <string>
#include <vector>

#include "codec_sections.h"
#include "entropy.h"
#include "permutation_coder.h"
#include "qsp/error.h"

namespace qsp {
namespace {

// A polygon file's rotations: a quad's as a quad file codes them (context: the previous quad's), any
// other face's r < d through an integer model by whether it is a triangle.
struct RotationCoder {
  std::array<BitModel, 3 * 4> quad{};
  IntModel other[2];
  unsigned previous = 0;  // the previous quad's rotation

  // A quad's rotation r: its high bit, then its low bit, in the context of the previous quad's.
  void encode_quad(RangeEncoder& enc, unsigned r) {
    enc.encode_bit(quad[3 * previous], r >> 1);
    enc.encode_bit(quad[3 * previous + 1 + (r >> 1)], r & 1u);
    previous = r;
  }
  unsigned decode_quad(RangeDecoder& dec) {
    const unsigned hi = dec.decode_bit(quad[3 * previous]);
    const unsigned lo = dec.decode_bit(quad[3 * previous + 1 + hi]);
    previous = 2 * hi + lo;
    return previous;
  }
};

}  // namespace

std::string encode_polygon_order(std::span<const std::uint32_t> vertex, std::span<const std::uint32_t> face,
                                 std::span<const std::uint32_t> rotation,
                                 std::span<const std::uint32_t> degree) {
  std::string out;
  RangeEncoder enc(out);
  const auto nv = static_cast<std::uint32_t>(vertex.size()), nf = static_cast<std::uint32_t>(face.size());
  if (rotation.size() != nf || degree.size() != nf) throw Error(ErrorCode::kInternal, "encode_order: sizes");
  PermutationCoder vertices, faces;
  RotationCoder rc;
  for (std::uint32_t v : vertex) vertices.encode(enc, v, nv);
  for (std::uint32_t f = 0; f < nf; ++f) {
    faces.encode(enc, face[f], nf);
    const std::uint32_t r = rotation[f], d = degree[face[f]];
    if (r >= d) throw Error(ErrorCode::kInternal, "encode_order: a rotation past its face's degree");
    if (d == 4) {
      rc.encode_quad(enc, r);
    } else {
      rc.other[d == 3 ? 0 : 1].encode(enc, r);
    }
  }
  enc.finish();
  return out;
}

PolygonOrder decode_polygon_order(std::string_view payload, std::uint64_t base_offset,
                                  std::uint32_t vertex_count, std::span<const std::uint32_t> degree) {
  RangeDecoder dec(payload, base_offset, "order section");
  const auto nf = static_cast<std::uint32_t>(degree.size());
  PolygonOrder order;
  order.vertex.resize(vertex_count);
  order.face.resize(nf);
  order.rotation.resize(nf);
  PermutationCoder vertices, faces;
  RotationCoder rc;
  std::vector<std::uint8_t> used(vertex_count, 0);
  for (std::uint32_t v = 0; v < vertex_count; ++v)
    order.vertex[v] = vertices.decode(dec, vertex_count, used, "vertex");
  used.assign(nf, 0);
  for (std::uint32_t f = 0; f < nf; ++f) {
    order.face[f] = faces.decode(dec, nf, used, "face");
    const std::uint32_t d = degree[order.face[f]];
    if (d == 4) {
      order.rotation[f] = rc.decode_quad(dec);
    } else {
      order.rotation[f] = rc.other[d == 3 ? 0 : 1].decode(dec);
      if (order.rotation[f] >= d)
        throw Error(ErrorCode::kFormat, "order section: face " + std::to_string(f) + " rotated by " +
                                            std::to_string(order.rotation[f]) + " of its " +
                                            std::to_string(d) + " corners (near byte offset " +
                                            std::to_string(dec.offset()) + ")");
    }
  }
  dec.finish();
  return order;
}

// A quad file's order section is a polygon file's with every face a quad.
std::string encode_order(const OrderMap& order) {
  const std::vector<std::uint32_t> rotation(order.rotation.begin(), order.rotation.end());
  const std::vector<std::uint32_t> degree(order.face.size(), 4);
  return encode_polygon_order(order.vertex, order.face, rotation, degree);
}

OrderMap decode_order(std::string_view payload, std::uint64_t base_offset, std::uint32_t vertex_count,
                      std::uint32_t face_count) {
  const std::vector<std::uint32_t> degree(face_count, 4);
  PolygonOrder p = decode_polygon_order(payload, base_offset, vertex_count, degree);
  OrderMap order;
  order.vertex = std::move(p.vertex);
  order.face = std::move(p.face);
  order.rotation.assign(p.rotation.begin(), p.rotation.end());
  return order;
}

}  // namespace qsp
