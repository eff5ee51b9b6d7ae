// The geometry section's header (format-spec/geometry_section.md, "Header"): the tools byte, the
// quantization bits, and the grid or the three axis descriptors.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "bytes.h"
#include "geometry_values.h"
#include "qsp/geometry.h"

namespace qsp {

struct Header {
  std::uint8_t tools = 0;         // geometry_tool bits
  std::uint32_t bits = 0;         // 0 lossless, else quantized
  std::array<AxisPlan, 3> plans;  // lossless
  Grid grid;                      // quantized

  bool has(std::uint8_t tool) const { return (tools & tool) != 0; }
  bool integer_axis(int a) const {
    return bits != 0 || plans[static_cast<std::size_t>(a)].mode != kFloatBits;
  }
  bool any_integer_axis() const { return integer_axis(0) || integer_axis(1) || integer_axis(2); }
  bool integer_axes() const { return integer_axis(0) && integer_axis(1) && integer_axis(2); }
  // The largest valid residual length of axis a.
  int max_length(int a) const {
    return bits                                                    ? static_cast<int>(bits)
           : plans[static_cast<std::size_t>(a)].mode == kFloatBits ? kFloatMaxLength
                                                                   : kDecimalMaxLength;
  }
};

void write_header(std::string& out, const Header& h);

// Reads a header for `count` vertices, checking every field (Error(kFormat) through `in`).
Header read_header(ByteReader& in, std::uint32_t count);

}  // namespace qsp
