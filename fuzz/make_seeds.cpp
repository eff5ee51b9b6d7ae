// Writes the fuzzers' seed corpora from testdata/ (and ../shared/meshes when present) at run time, so
// no corpus is committed: OUT/read_obj, OUT/read_off, OUT/read_ply, OUT/roundtrip (meshes) and
// OUT/decode_qsp (.qsp files the current encoder writes, in every mode, polygon files included), OUT/submesh
// (polygon arrays in fuzz/submesh.cpp's bytes). Usage: qsp_fuzz_seeds OUT TESTDATA [SHARED]
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"
#include "qsp/polymesh.h"

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxSeed =
    16384;  // hardening.sh passes -max_len 16384 (obj/off/roundtrip) / 32768 (qsp)
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
      for (int x = 0; x < 3; ++x)
        t.positions.insert(t.positions.end(), {float(x), float(y), float(x * y) * 0.5f});
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

// PLY in the three encodings, with an extra vertex property and a uchar/uint index list.
std::string write_ply(const qsp::QuadMesh& m, int encoding) {
  static const char* formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
  std::string out = std::string("ply\nformat ") + formats[encoding] +
                    " 1.0\ncomment qsp fuzz seed\nelement vertex " + std::to_string(m.vertex_count()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(m.face_count()) +
                    "\nproperty list uchar uint vertex_indices\nend_header\n";
  auto put32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) {
      const int shift = encoding == 1 ? 8 * i : 8 * (3 - i);
      out.push_back(static_cast<char>((v >> shift) & 0xFF));
    }
  };
  for (std::size_t i = 0; i < m.positions.size(); i += 3) {
    for (int k = 0; k < 3; ++k) {
      if (encoding == 0) {
        out += (k ? " " : "") + std::to_string(m.positions[i + k]);
      } else {
        put32(std::bit_cast<std::uint32_t>(m.positions[i + k]));
      }
    }
    if (encoding == 0) out += "\n";
  }
  for (std::size_t f = 0; f < m.quads.size(); f += 4) {
    if (encoding == 0) {
      out += "4";
      for (int c = 0; c < 4; ++c) out += " " + std::to_string(m.quads[f + c]);
      out += "\n";
    } else {
      out.push_back(4);
      for (int c = 0; c < 4; ++c) put32(m.quads[f + c]);
    }
  }
  return out;
}

// A polygon mesh in fuzz/submesh.cpp's bytes (vertex count - 1, then per face degree - 1 and its
// vertices); meshes of more than 64 vertices do not fit.
std::string submesh_bytes(std::uint32_t nv, const std::vector<std::vector<std::uint32_t>>& faces) {
  std::string out(1, static_cast<char>(nv - 1));
  for (const auto& f : faces) {
    out.push_back(static_cast<char>(f.size() - 1));
    for (std::uint32_t v : f) out.push_back(static_cast<char>(v));
  }
  return out;
}

// Polygon seeds the quad files lack: a tetrahedron, a 3x3 grid with a triangle pair in the middle,
// a pentagon fan, a quad on an edge with three faces.
std::vector<std::string> polygon_seeds() {
  std::vector<std::vector<std::uint32_t>> grid;
  for (std::uint32_t j = 0; j < 3; ++j)
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t a = 4 * j + i, b = a + 1, c = a + 5, d = a + 4;
      if (i == 1 && j == 1) {
        grid.push_back({a, b, d});
        grid.push_back({b, c, d});
      } else {
        grid.push_back({a, b, c, d});
      }
    }
  return {submesh_bytes(4, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}}), submesh_bytes(16, grid),
          submesh_bytes(7, {{0, 1, 2, 3, 4}, {0, 4, 5, 6, 1}}),
          submesh_bytes(8, {{0, 1, 2, 3}, {1, 0, 4, 5}, {0, 1, 6, 7}})};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s OUT TESTDATA [SHARED]\n", argv[0]);
    return 2;
  }
  const fs::path out = argv[1], testdata = argv[2];
  const fs::path obj = out / "read_obj", off = out / "read_off", ply = out / "read_ply",
                 rt = out / "roundtrip", qspdir = out / "decode_qsp", polygons = out / "submesh";
  for (const auto& d : {obj, off, ply, rt, qspdir, polygons}) fs::create_directories(d);
  for (const std::string& bytes : polygon_seeds())
    put(polygons, "p" + std::to_string(written) + ".bin", bytes);

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
    if (ext != ".obj" && ext != ".off" && ext != ".qsp" && ext != ".ply") continue;
    if (fs::file_size(p) > 4 * kMaxSeed) continue;
    const std::string bytes = slurp(p);
    const std::string name = std::to_string(n++) + "_" + p.filename().string();
    if (ext == ".qsp" || ext == ".ply") {
      put(ext == ".qsp" ? qspdir : ply, name, bytes, ext == ".qsp" ? 2 * kMaxSeed : kMaxSeed);
      continue;
    }
    put(ext == ".obj" ? obj : off, name, bytes);
    if (ext == ".obj") put(rt, name, bytes);
    try {
      qsp::QuadMesh m = ext == ".obj" ? qsp::read_obj(bytes, p.string()) : qsp::read_off(bytes, p.string());
      (void)qsp::build_adjacency(m);
      valid.push_back(std::move(m));
    } catch (const qsp::Error&) {
      // A polygon mesh (faces not quads, non-manifold, mis-oriented): format 3.1 files with the polygons
      // section, with and without the order section.
      try {
        const qsp::PolygonMesh poly = qsp::to_polygon_mesh(
            ext == ".obj" ? qsp::read_obj_mesh(bytes, p.string()) : qsp::read_off_mesh(bytes, p.string()), 0);
        for (int keep = 0; keep < 2; ++keep) {
          qsp::EncodeOptions o;
          o.keep_order = keep == 1;
          put(qspdir, "poly_" + name + "_" + std::to_string(keep) + ".qsp", qsp::encode_polygons(poly, o),
              2 * kMaxSeed);
        }
      } catch (const qsp::Error&) {
      }
    }
  }
  n = 0;
  for (const qsp::QuadMesh& m : valid) {
    const std::string id = "m" + std::to_string(n++);
    put(off, id + ".off", qsp::write_off(m));
    for (int encoding = 0; encoding < 3; ++encoding)
      put(ply, id + "_" + std::to_string(encoding) + ".ply", write_ply(m, encoding));
    put(rt, id + ".obj", qsp::write_obj(m));
    if (m.vertex_count() <= 64) {
      std::vector<std::vector<std::uint32_t>> faces;
      for (std::size_t f = 0; f < m.quads.size(); f += 4) faces.emplace_back(&m.quads[f], &m.quads[f] + 4);
      if (m.vertex_count() > 0)
        put(polygons, id + ".bin", submesh_bytes(static_cast<std::uint32_t>(m.vertex_count()), faces));
    }
    for (int mode = 0; mode < 4; ++mode) {  // lossless, keep-order, 11 bits, 11 bits at --best (costly tools)
      qsp::EncodeOptions o;
      o.keep_order = mode == 1;
      o.quantize_bits = mode >= 2 ? 11 : 0;
      if (mode == 3) o.level = qsp::kMaxLevel;
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
