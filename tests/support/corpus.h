// The meshes every property test runs over (testdata/ and, when present, ../shared), the invalid ones,
// their NAME.expect sidecars, and what ../shared/meshes/MANIFEST.tsv says each shared file must be.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp::testing {

// The shared folder: QSP_SHARED_DIR from the environment when set (to run as a clone without it would,
// e.g. QSP_SHARED_DIR=/nonexistent), else the build's ../shared.
inline std::filesystem::path shared_dir() {
  const char* env = std::getenv("QSP_SHARED_DIR");
  return std::filesystem::path(env && *env ? env : QSP_SHARED_DIR);
}

inline bool shared_present() { return std::filesystem::exists(shared_dir() / "meshes" / "MANIFEST.tsv"); }

// CI (which sets CI=true) and QSP_REQUIRE_SHARED=1 must not pass with the shared meshes missing.
inline bool shared_required() {
  const char* ci = std::getenv("CI");
  const char* req = std::getenv("QSP_REQUIRE_SHARED");
  return (ci && std::string(ci) == "true") || (req && std::string(req) == "1");
}

// In a test that needs ../shared/meshes: skips it (saying so) in a plain clone, fails it where the
// shared meshes are required.
#define QSP_NEEDS_SHARED()                                                \
  do {                                                                    \
    if (!::qsp::testing::shared_present()) {                              \
      if (::qsp::testing::shared_required())                              \
        FAIL() << ::qsp::testing::shared_dir() / "meshes"                 \
               << " is missing (required: CI=true or "                    \
               << "QSP_REQUIRE_SHARED=1)";                                \
      GTEST_SKIP() << "needs " << ::qsp::testing::shared_dir() / "meshes" \
                   << ", absent";                                         \
    }                                                                     \
  } while (0)

// One row of a MANIFEST.tsv (../shared/meshes and its osd_shapes/ have one each): column -> text.
struct ManifestRow {
  std::map<std::string, std::string> col;
  long num(const std::string& key) const { return std::stol(col.at(key)); }
  // A valid quad mesh, as qsp must accept it: quads only, manifold, oriented, no repeated vertex.
  bool valid() const {
    return col.at("all_quad") == "True" && num("nonmanifold_edges") == 0 &&
           num("nonmanifold_vertices") == 0 && num("flipped_edges") == 0 && num("degenerate_faces") == 0;
  }
  // A polygon mesh, as qsp compress must store it (format 3.1): no face repeats a vertex.
  bool mesh() const { return num("degenerate_faces") == 0; }
};

// File name -> row; empty if the manifest is missing.
inline std::map<std::string, ManifestRow> read_manifest(const std::filesystem::path& tsv) {
  std::map<std::string, ManifestRow> rows;
  std::ifstream in(tsv);
  std::string line;
  if (!std::getline(in, line)) return rows;
  std::vector<std::string> header;
  auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::stringstream ss(l);
    for (std::string cell; std::getline(ss, cell, '\t');) out.push_back(cell);
    return out;
  };
  header = split(line);
  while (std::getline(in, line)) {
    const auto cells = split(line);
    if (cells.empty()) continue;
    ManifestRow r;
    for (std::size_t i = 0; i < cells.size() && i < header.size(); ++i) r.col[header[i]] = cells[i];
    rows[cells[0]] = r;
  }
  return rows;
}

// The shared folders with a manifest, the folder of each.
inline std::vector<std::filesystem::path> shared_mesh_dirs() {
  return {shared_dir() / "meshes", shared_dir() / "meshes" / "osd_shapes"};
}

// What `path`'s manifest row says by `says` (a ManifestRow member: valid or mesh); true for every mesh in
// testdata/ (outside invalid/). A shared file without a row fails the test.
inline bool manifest_says(const std::filesystem::path& path, bool (ManifestRow::*says)() const) {
  namespace fs = std::filesystem;
  static std::map<fs::path, std::map<std::string, ManifestRow>> manifests;
  const fs::path dir = path.parent_path();
  for (const fs::path& d : shared_mesh_dirs()) {
    if (fs::exists(d) && fs::equivalent(d, dir)) {
      auto it = manifests.find(d);
      if (it == manifests.end()) it = manifests.emplace(d, read_manifest(d / "MANIFEST.tsv")).first;
      const auto row = it->second.find(path.filename().string());
      EXPECT_NE(row, it->second.end()) << path << " has no row in " << d / "MANIFEST.tsv";
      return row != it->second.end() && (row->second.*says)();
    }
  }
  return true;
}

// Whether `path` must be read as a valid quad mesh (the manifest's all_quad, manifold, oriented).
inline bool expected_valid(const std::filesystem::path& path) {
  return manifest_says(path, &ManifestRow::valid);
}

// Whether `path` must be stored by qsp compress as a polygon mesh (no face repeats a vertex).
inline bool expected_mesh(const std::filesystem::path& path) {
  return manifest_says(path, &ManifestRow::mesh);
}

// How many of `files` must be read as valid quad meshes (see expected_valid).
inline int expected_valid_count(const std::vector<std::filesystem::path>& files) {
  return static_cast<int>(std::count_if(files.begin(), files.end(), expected_valid));
}

inline std::vector<std::filesystem::path> mesh_files_in(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const auto ext = e.path().extension();
    if (ext == ".obj" || ext == ".off" || ext == ".ply") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The shared meshes with a manifest (../shared/meshes and osd_shapes/), sorted; empty without them.
inline std::vector<std::filesystem::path> shared_meshes() {
  std::vector<std::filesystem::path> out;
  for (const auto& d : shared_mesh_dirs())
    for (auto& p : mesh_files_in(d)) out.push_back(std::move(p));
  std::sort(out.begin(), out.end());
  return out;
}

// testdata/ (with golden/ and the hand-worked known-answers/) and, when present, the shared meshes.

inline std::vector<std::filesystem::path> corpus() {
  namespace fs = std::filesystem;
  std::vector<fs::path> out;
  for (const fs::path& d : {fs::path(QSP_TESTDATA_DIR), fs::path(QSP_TESTDATA_DIR) / "golden",
                            fs::path(QSP_TESTDATA_DIR) / "known-answers"})
    for (auto& p : mesh_files_in(d)) out.push_back(std::move(p));
  for (auto& p : shared_meshes()) out.push_back(std::move(p));
  std::sort(out.begin(), out.end());
  return out;
}

// Reads a corpus file and builds its adjacency. Returns false when qsp refuses it, after checking the
// refusal is a typed input error and that the file is one expected_valid says must be refused: a
// regression refusing valid meshes with a clean error fails every corpus loop, not only one.
inline bool read_valid(const std::filesystem::path& path, QuadMesh& m, Adjacency* adj = nullptr) {
  try {
    m = read_mesh_file(path.string());
    Adjacency a = build_adjacency(m);
    if (adj) *adj = std::move(a);
  } catch (const Error& e) {
    EXPECT_NE(e.code(), ErrorCode::kInternal) << path << ": " << e.what();
    EXPECT_FALSE(expected_valid(path)) << "a valid mesh was refused: " << e.what();
    return false;
  }
  EXPECT_TRUE(expected_valid(path)) << path
                                    << " was read, but its manifest row says it is not a valid quad mesh";
  return true;
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
