#include "load.h"

#include "files.h"
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

QuadMesh read_mesh_or_qsp(const std::string& path, ReadReport& report, MeshFormat format) {
  refuse_folder(path);
  format = format_for(path, format);
  std::string bytes;
  if (read_stdin_if_unknown(path, format, bytes)) {
    // Standard input may be a .qsp too: read once, then look.
    if (detect_format(bytes) != MeshFormat::kQsp) return read_mesh_bytes(bytes, path, &report);
  } else if (format != MeshFormat::kUnknown || format_from_path(path) != MeshFormat::kQsp) {
    return read_input_mesh(path, format, &report);
  } else {
    bytes = read_file_bytes(path);
  }
  try {
    return decode(bytes);
  } catch (const Error& e) {
    throw Error(e.code(), path + ": " + e.what());
  }
}

namespace {

LoadedMesh with_adjacency(LoadedMesh out, const std::string& path) {
  try {
    out.adjacency = build_adjacency(out.mesh);
  } catch (const Error& e) {
    rethrow_located(e, path, out.report);
  }
  return out;
}

}  // namespace

LoadedMesh load_mesh(const std::string& path, MeshFormat format) {
  LoadedMesh out;
  out.mesh = read_input_mesh(path, format, &out.report);
  return with_adjacency(std::move(out), path);
}

LoadedMesh load_mesh_bytes(std::string_view bytes, const std::string& path) {
  LoadedMesh out;
  out.mesh = read_mesh_bytes(bytes, path, &out.report);
  return with_adjacency(std::move(out), path);
}

// The geometry section's `bits` field, as inspect() read it.
int geometry_bits(const std::string&, const FileInfo& info) { return info.quantize_bits; }

bool read_stdin_if_unknown(const std::string& path, MeshFormat format, std::string& bytes) {
  if (path != "-" || format != MeshFormat::kUnknown) return false;
  bytes = read_file_bytes(path);
  return true;
}

}  // namespace qsp::cli
