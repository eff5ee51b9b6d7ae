// tools/qsp/load.h: reading a mesh for a subcommand, with every error located as file:line.
#pragma once

#include <string>

#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp::cli {

struct LoadedMesh {
  QuadMesh mesh;
  Adjacency adjacency;
  ReadReport report;
};

// Reads `path` (read_input_mesh, files.h: "-" and `format` as there) and builds its adjacency. An Error found
// at a face (non-manifold edge, orientation,
// ...) is rethrown as "path:LINE: ..." using the line the face came from. Throws qsp::Error.
LoadedMesh load_mesh(const std::string& path, MeshFormat format = MeshFormat::kUnknown);

// The same for a mesh whose bytes are already read (standard input, sniffed for a .qsp first).
LoadedMesh load_mesh_bytes(std::string_view bytes, const std::string& path);

// Standard input read whole when `path` is "-" and no format is given, so a subcommand that takes
// .qsp files too can look at its magic: true with `bytes` filled; false otherwise (read the path as
// usual). Throws Error(kIo) when standard input cannot be read.
bool read_stdin_if_unknown(const std::string& path, MeshFormat format, std::string& bytes);

// Reads a mesh file, or a .qsp decoded in full (vertices numbered as `qsp decompress` writes them);
// a decode error names the file. `report` gets the mesh file's face lines (none for a .qsp).
// `format` as read_input_mesh's (files.h): kUnknown = by name, else detected from the bytes.
QuadMesh read_mesh_or_qsp(const std::string& path, ReadReport& report,
                          MeshFormat format = MeshFormat::kUnknown);

// A .qsp's position precision: 0 lossless, 1..30 the quantization bits (the geometry section's `bits`
// field), -1 if `info` (inspect(bytes)) lists no geometry section. Reads only what inspect() checked.
int geometry_bits(const std::string& bytes, const FileInfo& info);

// Rethrows `e` with "path:LINE: " in front when it names a face the report has a line for.
[[noreturn]] void rethrow_located(const Error& e, const std::string& path, const ReadReport& report);

}  // namespace qsp::cli
