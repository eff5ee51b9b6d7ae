// libFuzzer target: the round trip. Any mesh the OBJ reader accepts and build_adjacency calls valid
// must compress and decompress to an isomorphic mesh (orientation included) with bit-identical
// positions; the bytes are canonical (re-encoding the decoded mesh gives them again); --keep-order
// restores the exact face list. Invalid meshes must be refused with a typed invalid-mesh error.
#include <cstdint>
#include <string_view>

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qsp;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  QuadMesh mesh;
  try {
    mesh = read_obj(text, "fuzz.obj");
  } catch (const Error& e) {
    fuzz::check_error(e, "read_obj");
    return 0;
  }
  fuzz::check_round_trip(mesh, "round trip");
  return 0;
}
