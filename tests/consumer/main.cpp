// Uses the installed qsp as a user would: encode a mesh, decode it, compare; prints the version.
#include <qsp/codec.h>
#include <qsp/error.h>
#include <qsp/version.h>

#include <cstdio>
#include <cstring>

int main() {
  qsp::QuadMesh mesh;  // a 2x1 strip of quads
  mesh.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
  mesh.quads = {0, 1, 4, 3, 1, 2, 5, 4};
  qsp::EncodeOptions options;
  options.keep_order = true;
  const std::string bytes = qsp::encode(mesh, options);
  const qsp::QuadMesh back = qsp::decode(bytes);
  const bool same = back.quads == mesh.quads && back.positions == mesh.positions;
  std::printf("qsp %s: %zu bytes, %s\n", qsp::version(), bytes.size(), same ? "round trip ok" : "MISMATCH");
  try {
    options.level = 42;
    (void)qsp::encode(mesh, options);
    return 1;
  } catch (const qsp::Error& e) {
    if (e.code() != qsp::ErrorCode::kUsage) return 1;
  }
  return same ? 0 : 1;
}
