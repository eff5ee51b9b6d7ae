// libFuzzer target: the OFF reader. Properties: no crash, no sanitizer report, only typed non-internal
// errors; an accepted mesh has finite positions, in-range indices and no degenerate face, writes back
// to OFF text that reads to the same mesh bit for bit, and build_adjacency refuses it cleanly or not at all.
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qsp;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  ReadReport report;
  QuadMesh mesh;
  try {
    mesh = read_off(text, "fuzz.off", &report);
  } catch (const Error& e) {
    fuzz::check_error(e, "read_off");
    return 0;
  }
  fuzz::check_reader_output(mesh, report, "read_off");
  try {
    const std::string again = write_off(mesh);
    QuadMesh back = read_off(again, "rewritten.off");
    if (back.quads != mesh.quads || !fuzz::same_bits(back.positions, mesh.positions)) {
      fuzz::finding("read_off(write_off(m)) != m");
    }
  } catch (const Error& e) {
    fuzz::finding(std::string("write_off/read_off of an accepted mesh failed: ") + e.what());
  }
  try {
    (void)build_adjacency(mesh);
  } catch (const Error& e) {
    fuzz::check_error(e, "build_adjacency");
    if (!fuzz::invalid_mesh_code(e.code())) fuzz::finding(std::string("build_adjacency: unexpected code: ") + e.what());
  }
  return 0;
}
