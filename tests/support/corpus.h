// The meshes every property test runs over (testdata/ and, when present, ../shared), the invalid ones,
// and their NAME.expect sidecars.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp::testing {

// Reads a corpus mesh and its adjacency; false for a mesh qsp refuses (non-quads, non-manifold),
// which must be refused with a clear error, never an internal one.
inline bool load_valid(const std::filesystem::path& path, QuadMesh& mesh, Adjacency& adj) {
  try {
    mesh = read_mesh_file(path.string());
    adj = build_adjacency(mesh);
    return true;
  } catch (const Error& e) {
    if (e.code() == ErrorCode::kInternal) ADD_FAILURE() << path << ": " << e.what();
    return false;
  }
}

inline std::vector<std::filesystem::path> corpus() {
  namespace fs = std::filesystem;
  std::vector<fs::path> out;
  auto add = [&](const fs::path& dir) {
    if (!fs::exists(dir)) return;
    for (const auto& e : fs::directory_iterator(dir)) {
      const auto ext = e.path().extension();
      if (ext == ".obj" || ext == ".off" || ext == ".ply") out.push_back(e.path());
    }
  };
  add(fs::path(QSP_TESTDATA_DIR));
  add(fs::path(QSP_TESTDATA_DIR) / "golden");
  add(fs::path(QSP_SHARED_DIR) / "meshes");
  add(fs::path(QSP_SHARED_DIR) / "meshes" / "osd_shapes");
  add(fs::path(QSP_SHARED_DIR) / "known-answers");
  std::sort(out.begin(), out.end());
  return out;
}

// Every mesh file (.obj .off .ply) in testdata/invalid and testdata/invalid/topology, sorted.
inline std::vector<std::filesystem::path> invalid_meshes() {
  namespace fs = std::filesystem;
  std::vector<fs::path> out;
  for (const fs::path& dir :
       {fs::path(QSP_TESTDATA_DIR) / "invalid", fs::path(QSP_TESTDATA_DIR) / "invalid" / "topology"}) {
    for (const auto& e : fs::directory_iterator(dir)) {
      const auto ext = e.path().extension();
      if (ext == ".obj" || ext == ".off" || ext == ".ply") out.push_back(e.path());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The `key=value` lines of a NAME.expect sidecar (`code=`, `message=`); empty if it is missing.
inline std::map<std::string, std::string> read_expect(const std::filesystem::path& path) {
  std::map<std::string, std::string> kv;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find('=');
    if (eq != std::string::npos) kv[line.substr(0, eq)] = line.substr(eq + 1);
  }
  return kv;
}

}  // namespace qsp::testing
