// The meshes every property test runs over: testdata/ and, when present, ../shared.
#pragma once

#include <algorithm>
#include <filesystem>
#include <vector>

namespace qsp::testing {

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

}  // namespace qsp::testing
