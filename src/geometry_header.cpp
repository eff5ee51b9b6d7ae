// The geometry section's header: see geometry_header.h.
#include "geometry_header.h"

#include <bit>
#include <cmath>

#include "geometry_coder.h"

namespace qsp {

void write_header(std::string& out, const Header& h) {
  put_u8(out, h.tools);
  put_u8(out, static_cast<std::uint8_t>(h.bits));
  if (h.bits) {
    for (float o : h.grid.origin) put_le(out, std::bit_cast<std::uint32_t>(o), 4);
    put_le(out, std::bit_cast<std::uint64_t>(h.grid.step), 8);
    return;
  }
  for (const AxisPlan& plan : h.plans) {
    put_u8(out, static_cast<std::uint8_t>(plan.mode | (plan.trailing_zeros ? kTrailingFlag : 0)));
    if (plan.mode == kFloatBits) continue;
    put_varint(out, plan.exceptions.size());
    std::uint32_t prev = 0;
    for (std::size_t e = 0; e < plan.exceptions.size(); ++e) {
      const Exception& x = plan.exceptions[e];
      put_varint(out, e == 0 ? x.vertex : x.vertex - prev - 1);
      put_le(out, std::bit_cast<std::uint32_t>(x.value), 4);
      prev = x.vertex;
    }
  }
}

Header read_header(ByteReader& in, std::uint32_t count) {
  Header h;
  const std::uint64_t tools_at = in.offset();
  h.tools = in.u8("tools");
  if (h.tools & ~geometry_tool::kAll) in.fail_at("reserved tool bits are set (must be zero)", tools_at);
  const std::uint64_t bits_at = in.offset();
  h.bits = in.u8("bits");
  if (h.bits > 30)
    in.fail_at("quantization bits " + std::to_string(h.bits) + " out of range (0 to 30)", bits_at);
  // Mirror prediction reflects integers: every axis must be one (checked once the plans are read).
  const auto mirror_needs_integers = [&] {
    if (h.has(geometry_tool::kMirror) && !h.integer_axes())
      in.fail_at("mirror prediction on an axis of float bits", tools_at);
  };
  if (h.bits) {
    for (float& o : h.grid.origin) {
      const std::uint64_t at = in.offset();
      o = std::bit_cast<float>(static_cast<std::uint32_t>(in.le(4, "grid origin")));
      if (!std::isfinite(o)) in.fail_at("grid origin not finite", at);
    }
    const std::uint64_t at = in.offset();
    h.grid.step = std::bit_cast<double>(in.le(8, "grid step"));
    if (!std::isfinite(h.grid.step) || std::signbit(h.grid.step) ||
        (std::bit_cast<std::uint64_t>(h.grid.step) & kStepLowMask)) {
      in.fail_at("invalid grid step", at);
    }
    mirror_needs_integers();
    return h;
  }
  for (AxisPlan& plan : h.plans) {
    const std::uint64_t at = in.offset();
    plan.mode = in.u8("axis mode");
    plan.trailing_zeros = (plan.mode & kTrailingFlag) != 0;
    plan.mode &= static_cast<std::uint8_t>(~kTrailingFlag);
    if (plan.mode > 1 + kMaxDecimals || (plan.trailing_zeros && plan.mode == kFloatBits))
      in.fail_at("unknown axis mode", at);
    if (plan.mode == kFloatBits) continue;
    const std::uint64_t count_at = in.offset();
    const std::uint64_t n = in.varint("exception count");
    if (n > count || n > in.left() / 5) in.fail_at("exception count exceeds the data", count_at);
    plan.exceptions.resize(n);
    std::uint64_t prev = 0;
    for (std::uint64_t e = 0; e < n; ++e) {
      const std::uint64_t gap_at = in.offset();
      const std::uint64_t gap = in.varint("exception");
      const std::uint64_t v = e == 0 ? gap : prev + 1 + gap;
      if (gap >= count || v >= count) in.fail_at("exception vertex out of range", gap_at);
      plan.exceptions[e].vertex = static_cast<std::uint32_t>(v);
      plan.exceptions[e].value = std::bit_cast<float>(static_cast<std::uint32_t>(in.le(4, "exception")));
      prev = v;
    }
  }
  mirror_needs_integers();
  return h;
}

std::uint8_t geometry_tools(std::string_view bytes, std::uint64_t base_offset) {
  ByteReader in(bytes, base_offset, "geometry section");
  const std::uint8_t tools = in.u8("tools");
  if (tools & ~geometry_tool::kAll) in.fail_at("reserved tool bits are set (must be zero)", base_offset);
  return tools;
}

std::uint8_t geometry_quantize_bits(std::string_view bytes, std::uint64_t base_offset) {
  (void)geometry_tools(bytes, base_offset);
  ByteReader in(bytes.substr(1), base_offset + 1, "geometry section");
  const std::uint8_t bits = in.u8("bits");
  if (bits > 30)
    in.fail_at("quantization bits " + std::to_string(bits) + " out of range (0 to 30)", base_offset + 1);
  return bits;
}

std::string geometry_tool_names(std::uint8_t tools) {
  std::string out;
  auto add = [&](std::uint8_t bit, const char* name) {
    if (!(tools & bit)) return;
    if (!out.empty()) out += ", ";
    out += name;
  };
  add(geometry_tool::kValueRepeats, "value repeats");
  add(geometry_tool::kNormalChaining, "normal chaining");
  add(geometry_tool::kCellShapes, "cell shapes");
  add(geometry_tool::kLogisticMixing, "logistic mixing");
  add(geometry_tool::kMirror, "mirror prediction");
  return out.empty() ? "none" : out;
}

}  // namespace qsp
