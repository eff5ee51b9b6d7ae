// The geometry decoder: the header, then the decoder's side of the coding loop (geometry_loop.h), which
// reads each coordinate's repeat or residual from the range coder and checks it against its domain.
#include <cmath>
#include <limits>

#include "geometry_coder.h"
#include "geometry_loop.h"
#include "geometry_repeats.h"

namespace qsp {
namespace {

template <bool kLogistic>
class GeometryDecoder {
 public:
  GeometryDecoder(const Header& h, Values& values, RangeDecoder& rc, std::vector<float>& out)
      : h_(h), values_(values), rc_(rc), out_(out), model_(kLogistic) {
    if (h.bits) qmax_ = static_cast<std::int64_t>((std::uint64_t{1} << h.bits) - 1);
  }

  static constexpr ChainCue* cue() { return nullptr; }

  // Inlined into the loop (as one function, its contexts never leave registers): 3% of the decode.
  [[gnu::always_inline]] Coded code(const Coordinate& c) {
    const auto a = static_cast<std::size_t>(c.axis);
    float& out = out_[3 * std::size_t{c.vertex} + a];
    std::int64_t value = 0;
    const bool hit = !c.exception && repeat(c, value);
    std::uint64_t u;
    if (h_.bits) {
      if (hit) {
        u = zigzag64(wrapped(value - c.pred, qmax_));
      } else {
        u = model_.template decode<kLogistic>(rc_, c.context);
        value = (c.pred + unzigzag64(u)) & qmax_;
      }
      values_.ints[a][c.vertex] = value;
      out = h_.grid.value(c.axis, value);
    } else if (h_.integer_axis(c.axis)) {
      const AxisPlan& plan = h_.plans[a];
      if (hit) {
        u = zigzag64(value - c.pred);
      } else {
        u = model_.template decode<kLogistic>(rc_, c.context);
        if (plan.trailing_zeros) {
          const int t = model_.decode_zeros(rc_, std::min(decimal_digits(c.pred), 15));
          if (t < 0) fail("too many trailing zeros");
          const std::int64_t unit = kPow10i[static_cast<std::size_t>(t)];
          const std::int64_t m = rounded_unit(c.pred, t) + unzigzag64(u);
          // |m * 10^t| < 2^40; 10^t does not divide 2^40 for t > 0, so compare against (2^40 - 1) / 10^t.
          if (m < -((kDecimalLimit - 1) / unit) || m > (kDecimalLimit - 1) / unit)
            fail("decimal integer out of range");
          value = m * unit;
        } else {
          value = c.pred + unzigzag64(u);
        }
        if (value <= -kDecimalLimit || value >= kDecimalLimit) fail("decimal integer out of range");
      }
      values_.ints[a][c.vertex] = value;
      out = c.exception ? c.exception->value : decimal_float(value, plan.mode - 1);
    } else {
      if (hit) {
        u = zigzag64(value - c.pred);
      } else {
        u = model_.template decode<kLogistic>(rc_, c.context);
        value = c.pred + unzigzag64(u);
        if (value < 0 || value > 0xFFFFFFFFll) fail("float residual out of range");
      }
      out = values_.floats[a][c.vertex] = image_float(static_cast<std::uint32_t>(value));
    }
    if (h_.has(geometry_tool::kValueRepeats) && !c.exception) seen_[a].insert(value);
    return {u, hit};
  }

 private:
  // The repeat decision and rank, if the tool is on and the axis has values; true and `value` set if
  // the stream says the coordinate repeats one.
  bool repeat(const Coordinate& c, std::int64_t& value) {
    if (!h_.has(geometry_tool::kValueRepeats)) return false;
    const Repeats& seen = seen_[static_cast<std::size_t>(c.axis)];
    if (seen.empty() || !rc_.decode_bit(model_.repeat(c.context.kind, c.previous))) return false;
    const std::uint32_t k = model_.rank.decode(rc_);
    if (k > Repeats::kMaxRank || !seen.nth(c.pred, k, value)) fail("repeat rank out of range");
    return true;
  }
  [[noreturn]] void fail(const char* what) const {
    throw Error(ErrorCode::kFormat, std::string("geometry section: ") + what + " (at byte offset " +
                                        std::to_string(rc_.offset()) + ")");
  }

  const Header& h_;
  Values& values_;
  RangeDecoder& rc_;
  std::vector<float>& out_;
  ResidualModel model_;
  std::int64_t qmax_ = 0;
  std::array<Repeats, 3> seen_;
};

// The section's vertices, with the logistic mixing tool or without.
template <bool kLogistic>
void decode_vertices(const Header& h, const Hoods& hoods, Values& values, RangeDecoder& rc,
                     std::vector<float>& out) {
  GeometryDecoder<kLogistic> io(h, values, rc, out);
  if (h.has(geometry_tool::kCellShapes)) {
    code_vertices<GeometryDecoder<kLogistic>, true, kLogistic>(h, hoods, hoods.size(), values, io);
  } else {
    code_vertices<GeometryDecoder<kLogistic>, false, kLogistic>(h, hoods, hoods.size(), values, io);
  }
}

}  // namespace

std::vector<float> decode_geometry(std::string_view bytes, std::uint64_t base_offset,
                                   std::span<const Stencil> stencil, std::uint32_t vertex_count) {
  check_stencils(stencil, vertex_count);
  ByteReader in(bytes, base_offset, "geometry section");
  const Header h = read_header(in, vertex_count);
  const std::uint64_t payload_at = in.offset();
  RangeDecoder rc(in.rest(), payload_at, "geometry section: payload");
  const Hoods hoods(stencil, coding_order(h.tools));
  Values values;
  for (std::size_t a = 0; a < 3; ++a)
    (h.integer_axis(static_cast<int>(a)) ? values.ints[a].resize(vertex_count)
                                         : values.floats[a].resize(vertex_count));
  std::vector<float> out(std::size_t{vertex_count} * 3);
  if (h.has(geometry_tool::kLogisticMixing)) {
    decode_vertices<true>(h, hoods, values, rc, out);
  } else {
    decode_vertices<false>(h, hoods, values, rc, out);
  }
  rc.finish();
  return out;
}

double max_geometry_error(std::span<const float> original, std::span<const float> decoded) {
  if (original.size() != decoded.size()) throw Error(ErrorCode::kUsage, "geometry: sizes differ");
  double worst = 0;
  for (std::size_t i = 0; i < original.size(); ++i) {
    if (std::bit_cast<std::uint32_t>(original[i]) == std::bit_cast<std::uint32_t>(decoded[i])) continue;
    const double d = std::fabs(static_cast<double>(original[i]) - static_cast<double>(decoded[i]));
    if (std::isnan(d)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, d);
  }
  return worst;
}

}  // namespace qsp
