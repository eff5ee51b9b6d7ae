// A permutation coded as the step from "one after the previous value" (small where the original order
// runs along the canonical one): the order section's vertices and faces, and the texture coordinates
// section's original numbering (format-spec/qsp_format.md, "Order section").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "entropy.h"
#include "qsp/error.h"

namespace qsp {

// Signed step in (-n/2, n/2] from the prediction to `value`, both in [0, n), zigzagged (<= n).
inline std::uint32_t step_code(std::uint32_t value, std::uint32_t predicted, std::uint32_t n) {
  std::uint64_t r = (std::uint64_t{value} + n - predicted) % n;
  std::int64_t s = 2 * r <= n ? static_cast<std::int64_t>(r) : static_cast<std::int64_t>(r) - n;
  return zigzag(s);
}

struct PermutationCoder {
  IntModel step[2];  // by whether the previous step was 0
  std::uint32_t predicted = 0;
  unsigned previous_zero = 1;
  const char* section = "order section";  // for messages

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
      throw Error(ErrorCode::kFormat, std::string(section) + ": " + what +
                                          " step out of range (near byte offset " +
                                          std::to_string(dec.offset()) + ")");
    }
    auto value = static_cast<std::uint32_t>((static_cast<std::int64_t>(predicted) + s + n) % n);
    if (used[value]) {
      throw Error(ErrorCode::kFormat, std::string(section) + ": " + what + " " + std::to_string(value) +
                                          " used twice, not a permutation (near byte offset " +
                                          std::to_string(dec.offset()) + ")");
    }
    used[value] = 1;
    previous_zero = code == 0;
    predicted = value + 1 == n ? 0 : value + 1;
    return value;
  }
};

}  // namespace qsp
