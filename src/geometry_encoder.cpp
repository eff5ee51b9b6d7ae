// The geometry encoder's side of the coding loop (geometry_loop.h): every value is known, and each
// coordinate becomes symbols for the sink (a repeat decision and rank, a residual, trailing zeros).
#include "geometry_encoder.h"

#include "geometry_coder.h"
#include "geometry_loop.h"
#include "geometry_repeats.h"
#include "geometry_sink.h"

namespace qsp {
namespace {

class GeometryEncoder {
 public:
  GeometryEncoder(const Header& h, Values& values, std::uint32_t count, SymbolSink& sink, ChainCue* cue)
      : h_(h), values_(values), sink_(sink), cue_(cue) {
    if (h.bits) qmax_ = static_cast<std::int64_t>((std::uint64_t{1} << h.bits) - 1);
    if (!h.has(geometry_tool::kValueRepeats)) return;
    for (std::size_t a = 0; a < 3; ++a) {  // every value each axis will insert: exceptions never do
      std::vector<std::int64_t> planned;
      planned.reserve(count);
      const bool is_int = h.integer_axis(static_cast<int>(a));
      const std::vector<Exception>* ex = is_int && !h.bits ? &h.plans[a].exceptions : nullptr;
      std::size_t e = 0;
      for (std::uint32_t i = 0; i < count; ++i) {
        if (ex && e < ex->size() && (*ex)[e].vertex == i) {
          ++e;
          continue;
        }
        planned.push_back(is_int ? values.ints[a][i]
                                 : static_cast<std::int64_t>(float_image(values.floats[a][i])));
      }
      ranks_[a] = RepeatRanks(std::move(planned));
    }
  }

  ChainCue* cue() { return cue_; }

  // Inlined into the loop, as the decoder's is.
  [[gnu::always_inline]] Coded code(const Coordinate& c) {
    const auto a = static_cast<std::size_t>(c.axis);
    const bool is_int = h_.integer_axis(c.axis);
    std::int64_t value;
    if (!is_int) {
      value = float_image(values_.floats[a][c.vertex]);
    } else {
      std::int64_t& v = values_.ints[a][c.vertex];
      if (c.exception) v = c.pred;  // its float is stored aside: residual zero keeps neighbours smooth
      value = v;
    }
    const bool hit = !c.exception && repeat(c, value);
    const std::uint64_t u = zigzag64(h_.bits ? wrapped(value - c.pred, qmax_) : value - c.pred);
    if (hit) return {u, true};
    const AxisPlan& plan = h_.plans[a];
    if (!h_.bits && plan.mode != kFloatBits && plan.trailing_zeros) {
      // n = 10^t * m: the residual of m against the prediction rounded to units of 10^t, then t.
      const int t = trailing_zeros(value);
      const std::uint64_t um =
          zigzag64(value / kPow10i[static_cast<std::size_t>(t)] - rounded_unit(c.pred, t));
      put_residual(um, c);
      sink_.put({static_cast<std::uint64_t>(t), Symbol::kZeros, 0,
                 static_cast<std::uint8_t>(std::min(decimal_digits(c.pred), 15)), 0});
      return {um, false};
    }
    put_residual(u, c);
    return {u, false};
  }

 private:
  // The repeat decision and rank, if the tool is on and the axis has values; true if `value` repeats.
  bool repeat(const Coordinate& c, std::int64_t value) {
    if (!h_.has(geometry_tool::kValueRepeats)) return false;
    RepeatRanks& ranks = ranks_[static_cast<std::size_t>(c.axis)];
    const std::size_t slot = ranks.slot(value);
    bool hit = false;
    if (!ranks.empty()) {
      const std::uint32_t k = ranks.rank_of(c.pred, value, slot);
      // Stricter rules (rank 0 only, rank small against the residual) were measured worse overall.
      hit = k <= Repeats::kMaxRank;
      sink_.put({k, Symbol::kRepeat, static_cast<std::uint8_t>(c.context.kind),
                 static_cast<std::uint8_t>(c.previous), static_cast<std::uint8_t>(hit)});
    }
    ranks.insert(slot);
    return hit;
  }
  void put_residual(std::uint64_t u, const Coordinate& c) {
    const ResidualContext& r = c.context;
    sink_.put({u, Symbol::kResidual, static_cast<std::uint8_t>(r.kind), static_cast<std::uint8_t>(r.cls),
               static_cast<std::uint8_t>(r.max_len), static_cast<std::uint8_t>(r.axis),
               static_cast<std::uint8_t>(r.neighbour_cls), static_cast<std::uint8_t>(r.previous)});
  }

  const Header& h_;
  Values& values_;
  SymbolSink& sink_;
  ChainCue* cue_;
  std::int64_t qmax_ = 0;
  std::array<RepeatRanks, 3> ranks_;
};

}  // namespace

std::string encode_with(std::span<const float> pos, const Hoods& hoods, std::uint32_t count, const Header& h,
                        std::optional<bool> coder_thread, ChainCue* cue) {
  Values values;
  for (std::size_t a = 0; a < 3; ++a) {
    const int axis = static_cast<int>(a);
    if (!h.integer_axis(axis)) {
      values.floats[a].resize(count);
      for (std::uint32_t i = 0; i < count; ++i) values.floats[a][i] = pos[3 * std::size_t{i} + a];
      continue;
    }
    values.ints[a].resize(count);
    if (h.bits && h.grid.all_finite(axis, h.bits)) {  // no test per value
      for (std::uint32_t i = 0; i < count; ++i)
        values.ints[a][i] = h.grid.nearest(axis, pos[3 * std::size_t{i} + a], h.bits);
      continue;
    }
    const std::vector<Exception>& ex = h.plans[a].exceptions;
    std::size_t e = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      const float x = pos[3 * std::size_t{i} + a];
      std::int64_t v = 0;
      if (h.bits) {
        v = h.grid.quantize(axis, x, h.bits);
      } else if (e < ex.size() && ex[e].vertex == i) {
        ++e;  // set to its prediction while coding
      } else {
        decimal_of(x, h.plans[a].mode - 1, v);
      }
      values.ints[a][i] = v;
    }
  }
  std::string out;
  write_header(out, h);
  std::string payload;
  {
    SymbolSink sink(h.has(geometry_tool::kLogisticMixing), payload,
                    coder_thread.value_or(count > kCoderThreadAbove));
    GeometryEncoder io(h, values, count, sink, cue);
    code_section(h, hoods, count, values, io);
    sink.finish();
  }
  out += payload;
  return out;
}

}  // namespace qsp
