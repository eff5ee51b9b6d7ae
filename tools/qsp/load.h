// tools/qsp/load.h: reading a mesh for a subcommand, with every error located as file:line.
#pragma once

#include <string>

#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp::cli {

struct LoadedMesh {
  QuadMesh mesh;
  Adjacency adjacency;
  ReadReport report;
};

// Reads `path` and builds its adjacency. An Error found at a face (non-manifold edge, orientation,
// ...) is rethrown as "path:LINE: ..." using the line the face came from. Throws qsp::Error.
LoadedMesh load_mesh(const std::string& path);

// Reads a mesh file, or a .qsp decoded in full (vertices numbered as `qsp decompress` writes them);
// a decode error names the file. `report` gets the mesh file's face lines (none for a .qsp).
QuadMesh read_mesh_or_qsp(const std::string& path, ReadReport& report);

// Rethrows `e` with "path:LINE: " in front when it names a face the report has a line for.
[[noreturn]] void rethrow_located(const Error& e, const std::string& path, const ReadReport& report);

}  // namespace qsp::cli
