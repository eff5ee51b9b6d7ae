// A mesh file read once for a test, with the library's reader (read_mesh_file: format by extension;
// throws qsp::Error as the reader does).
#pragma once

#include <filesystem>

#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp::testing {

inline QuadMesh load(const std::filesystem::path& path) { return read_mesh_file(path.string()); }

}  // namespace qsp::testing
