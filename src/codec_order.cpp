// The order section (--keep-order): where each original vertex and face went in the canonical order,
// coded as the step from "one after the previous one" (small when the original order runs along the
// same rows as the canonical one), plus each face's corner rotation. See qsp_format.md, "Order section".
#include <array>
#include <string>
#include <vector>

#include "codec_sections.h"
#include "entropy.h"
#include "qsp/error.h"

namespace qsp {
namespace {

// Signed step in (-n/2, n/2] from the prediction to `value`, both in [0, n), zigzagged (<= n).
std::uint32_t step_code(std::uint32_t value, std::uint32_t predicted, std::uint32_t n) {
  std::uint64_t r = (std::uint64_t{value} + n - predicted) % n;
  std::int64_t s = 2 * r <= n ? static_cast<std::int64_t>(r) : static_cast<std::int64_t>(r) - n;
  return zigzag(s);
}

struct PermutationCoder {
  IntModel step[2];  // by whether the previous step was 0
  std::uint32_t predicted = 0;
  unsigned previous_zero = 1;

  void encode(RangeEncoder& enc, std::uint32_t value, std::uint32_t n) {
    std::uint32_t code = step_code(value, predicted, n);
    step[previous_zero].encode(enc, code);
    previous_zero = code == 0;
    predicted = value + 1 == n ? 0 : value + 1;
  }
  std::uint32_t decode(RangeDecoder& dec, std::uint32_t n, std::vector<std::uint8_t>& used,
                       const char* what) {
    std::uint32_t code = step[previous_zero].decode(dec);
    std::int64_t s = unzigzag(code);
    if (2 * s > n || 2 * s <= -static_cast<std::int64_t>(n)) {
      throw Error(ErrorCode::kFormat, std::string("order section: ") + what +
                                          " step out of range (near byte offset " +
                                          std::to_string(dec.offset()) + ")");
    }
    auto value = static_cast<std::uint32_t>((static_cast<std::int64_t>(predicted) + s + n) % n);
    if (used[value]) {
      throw Error(ErrorCode::kFormat, std::string("order section: ") + what + " " + std::to_string(value) +
                                          " used twice, not a permutation (near byte offset " +
                                          std::to_string(dec.offset()) + ")");
    }
    used[value] = 1;
    previous_zero = code == 0;
    predicted = value + 1 == n ? 0 : value + 1;
    return value;
  }
};

}  // namespace

std::string encode_order(const OrderMap& order) {
  std::string out;
  RangeEncoder enc(out);
  auto nv = static_cast<std::uint32_t>(order.vertex.size());
  auto nf = static_cast<std::uint32_t>(order.face.size());
  if (order.rotation.size() != nf) throw Error(ErrorCode::kInternal, "encode_order: rotation size");
  PermutationCoder vertices, faces;
  std::array<BitModel, 3 * 4> rotation{};
  unsigned previous = 0;
  for (std::uint32_t v : order.vertex) vertices.encode(enc, v, nv);
  for (std::uint32_t f = 0; f < nf; ++f) {
    faces.encode(enc, order.face[f], nf);
    unsigned r = order.rotation[f] & 3u;
    enc.encode_bit(rotation[3 * previous], r >> 1);
    enc.encode_bit(rotation[3 * previous + 1 + (r >> 1)], r & 1u);
    previous = r;
  }
  enc.finish();
  return out;
}

OrderMap decode_order(std::string_view payload, std::uint64_t base_offset, std::uint32_t vertex_count,
                      std::uint32_t face_count) {
  RangeDecoder dec(payload, base_offset, "order section");
  OrderMap order;
  order.vertex.resize(vertex_count);
  order.face.resize(face_count);
  order.rotation.resize(face_count);
  PermutationCoder vertices, faces;
  std::array<BitModel, 3 * 4> rotation{};
  unsigned previous = 0;
  std::vector<std::uint8_t> used(vertex_count, 0);
  for (std::uint32_t v = 0; v < vertex_count; ++v)
    order.vertex[v] = vertices.decode(dec, vertex_count, used, "vertex");
  used.assign(face_count, 0);
  for (std::uint32_t f = 0; f < face_count; ++f) {
    order.face[f] = faces.decode(dec, face_count, used, "face");
    unsigned hi = dec.decode_bit(rotation[3 * previous]);
    unsigned lo = dec.decode_bit(rotation[3 * previous + 1 + hi]);
    previous = 2 * hi + lo;
    order.rotation[f] = static_cast<std::uint8_t>(previous);
  }
  dec.finish();
  return order;
}

}  // namespace qsp
