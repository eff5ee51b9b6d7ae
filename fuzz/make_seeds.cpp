// Writes the fuzzers' seed corpora from testdata/ (and ../shared/meshes when present) at run time, so
// no corpus is committed: OUT/read_obj, OUT/read_off, OUT/roundtrip (mesh text) and OUT/decode_qsp
// (.qsp files the current encoder writes, in every mode). Usage: qsp_fuzz_seeds OUT TESTDATA [SHARED]
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxSeed = 16384;  // hardening.sh passes -max_len 16384 (obj/off/roundtrip) / 32768 (qsp)
int written = 0;

void put(const fs::path& dir, const std::string& name, const std::string& bytes, std::size_t max = kMaxSeed) {
  if (bytes.size() > max) return;
  std::ofstream(dir / name, std::ios::binary) << bytes;
  ++written;
}

std::vector<fs::path> files(const fs::path& dir, bool recursive) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  auto add = [&](const fs::directory_entry& e) {
    if (e.is_regular_file()) out.push_back(e.path());
  };
  if (recursive) {
    for (const auto& e : fs::recursive_directory_iterator(dir)) add(e);
  } else {
    for (const auto& e : fs::directory_iterator(dir)) add(e);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Small meshes made in code: shapes the files may not have (empty, points only, a torus with twist).
std::vector<qsp::QuadMesh> made_meshes() {
  std::vector<qsp::QuadMesh> out;
  out.emplace_back();  // empty
  qsp::QuadMesh points;
  points.positions = {1, 2, 3, -0.0f, 5e-40f, 6};
  out.push_back(points);
  qsp::QuadMesh quad;
  quad.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 9, 9, 9};  // and an unreferenced vertex
  quad.quads = {0, 1, 2, 3};
  out.push_back(quad);
  for (int twist : {0, 1}) {  // 3x3 torus
    qsp::QuadMesh t;
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) t.positions.insert(t.positions.end(), {float(x), float(y), float(x * y) * 0.5f});
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) {
        auto P = [&](int i, int j) {
          if (j == 3) i += twist;
          return static_cast<std::uint32_t>((j % 3) * 3 + (i % 3));
        };
        t.quads.insert(t.quads.end(), {P(x, y), P(x + 1, y), P(x + 1, y + 1), P(x, y + 1)});
      }
    out.push_back(t);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s OUT TESTDATA [SHARED]\n", argv[0]);
    return 2;
  }
  const fs::path out = argv[1], testdata = argv[2];
  const fs::path obj = out / "read_obj", off = out / "read_off", rt = out / "roundtrip", qspdir = out / "decode_qsp";
  for (const auto& d : {obj, off, rt, qspdir}) fs::create_directories(d);

  std::vector<fs::path> inputs = files(testdata, true);
  if (argc > 3) {
    for (const char* sub : {"meshes", "meshes/osd_shapes"}) {
      auto more = files(fs::path(argv[3]) / sub, false);
      inputs.insert(inputs.end(), more.begin(), more.end());
    }
  }
  std::vector<qsp::QuadMesh> valid = made_meshes();
  int n = 0;
  for (const fs::path& p : inputs) {
    const std::string ext = p.extension().string();
    if (ext != ".obj" && ext != ".off" && ext != ".qsp") continue;
    if (fs::file_size(p) > 4 * kMaxSeed) continue;
    const std::string bytes = slurp(p);
    const std::string name = std::to_string(n++) + "_" + p.filename().string();
    if (ext == ".qsp") {
      put(qspdir, name, bytes, 2 * kMaxSeed);
      continue;
    }
    put(ext == ".obj" ? obj : off, name, bytes);
    if (ext == ".obj") put(rt, name, bytes);
    try {
      qsp::QuadMesh m = ext == ".obj" ? qsp::read_obj(bytes, p.string()) : qsp::read_off(bytes, p.string());
      (void)qsp::build_adjacency(m);
      valid.push_back(std::move(m));
    } catch (const qsp::Error&) {
    }
  }
  n = 0;
  for (const qsp::QuadMesh& m : valid) {
    const std::string id = "m" + std::to_string(n++);
    put(off, id + ".off", qsp::write_off(m));
    put(rt, id + ".obj", qsp::write_obj(m));
    for (int mode = 0; mode < 3; ++mode) {
      qsp::EncodeOptions o;
      o.keep_order = mode == 1;
      o.quantize_bits = mode == 2 ? 11 : 0;
      try {
        put(qspdir, id + "_" + std::to_string(mode) + ".qsp", qsp::encode(m, o), 2 * kMaxSeed);
      } catch (const qsp::Error& e) {
        std::fprintf(stderr, "qsp_fuzz_seeds: cannot encode mesh %d: %s\n", n - 1, e.what());
        return 1;
      }
    }
  }
  std::printf("qsp_fuzz_seeds: wrote %d seed files to %s\n", written, out.c_str());
  return 0;
}
