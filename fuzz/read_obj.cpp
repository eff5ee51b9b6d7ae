// libFuzzer target: the OBJ reader. Properties: no crash, no sanitizer report, only typed non-internal
// errors; an accepted mesh has finite positions, in-range indices and no degenerate face, writes back
// to OBJ text that reads to the same mesh bit for bit, and build_adjacency refuses it cleanly or not at all.
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  qsp::fuzz::check_text_reader(std::string_view(reinterpret_cast<const char*>(data), size), "obj",
                               &qsp::read_obj, [](const qsp::QuadMesh& m) { return qsp::write_obj(m); });
  return 0;
}
