#include "load.h"

#include "qsp/codec.h"
#include "qsp/error.h"

namespace qsp::cli {

void rethrow_located(const Error& e, const std::string& path, const ReadReport& report) {
  const std::int64_t f = e.face();
  if (f >= 0 && static_cast<std::size_t>(f) < report.face_line.size() && report.face_line[f] != 0)
    throw Error(e.code(), path + ":" + std::to_string(report.face_line[f]) + ": " + e.what(), f);
  if (f >= 0) throw Error(e.code(), path + ": " + e.what(), f);
  throw e;
}

QuadMesh read_mesh_or_qsp(const std::string& path, ReadReport& report) {
  if (format_from_path(path) != MeshFormat::kQsp) return read_mesh_file(path, &report);
  const std::string bytes = read_file_bytes(path);
  try {
    return decode(bytes);
  } catch (const Error& e) {
    throw Error(e.code(), path + ": " + e.what());
  }
}

LoadedMesh load_mesh(const std::string& path) {
  LoadedMesh out;
  out.mesh = read_mesh_file(path, &out.report);
  try {
    out.adjacency = build_adjacency(out.mesh);
  } catch (const Error& e) {
    rethrow_located(e, path, out.report);
  }
  return out;
}

}  // namespace qsp::cli
