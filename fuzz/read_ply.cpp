// libFuzzer target: the PLY reader (ascii, binary little and big endian), on the input bytes as they
// are (read_ply, which read_ply_file calls after reading the file). Properties as for read_obj: no
// crash, no sanitizer report, only typed non-internal errors, and an accepted mesh has finite
// positions, in-range indices and no degenerate face; build_adjacency refuses it cleanly or not at all.
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qsp;
  ReadReport report;
  QuadMesh mesh;
  try {
    mesh = read_ply(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.ply", &report);
  } catch (const Error& e) {
    fuzz::check_error(e, "read_ply");
    if (e.code() == ErrorCode::kIo)
      fuzz::finding(std::string("read_ply: I/O error on bytes in memory: ") + e.what());
    return 0;
  }
  fuzz::check_reader_output(mesh, report, "read_ply");
  fuzz::check_adjacency(mesh);
  return 0;
}
