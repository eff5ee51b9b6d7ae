// libFuzzer target: the OFF reader. Properties: no crash, no sanitizer report, only typed non-internal
// errors; an accepted mesh has finite positions, in-range indices and no degenerate face, writes back
// to OFF text that reads to the same mesh bit for bit, and build_adjacency refuses it cleanly or not at all.
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  qsp::fuzz::check_text_reader(std::string_view(reinterpret_cast<const char*>(data), size), "off",
                               &qsp::read_off, [](const qsp::QuadMesh& m) { return qsp::write_off(m); });
  return 0;
}
