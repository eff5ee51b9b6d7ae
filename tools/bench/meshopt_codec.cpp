// meshoptimizer's index and vertex codecs on a quad mesh, as a user of meshoptimizer would run them
// (for tools/bench/bench_codec.sh, beside qsp and Draco). Plain main(); needs libmeshoptimizer-dev.
//
//   meshopt_codec [--bits N] [--tsv] MESH.obj|.off|.ply
//
// meshoptimizer's index codec only takes triangle lists, so every quad (a,b,c,d) becomes the two
// triangles (a,b,c), (a,c,d). The pipeline is the one meshoptimizer's documentation recommends:
// meshopt_optimizeVertexCache, meshopt_optimizeVertexFetch (renumbers vertices in first-use order),
// meshopt_encodeIndexBuffer (format version 1), meshopt_encodeVertexBuffer, then a general-purpose
// compressor over each stream (zstd level 19 here). Two index variants:
//   quads kept: after optimizeVertexCache the quads are put in the order in which their first
//     triangle appears, with their two triangles next to each other, so triangles 2k and 2k+1 give
//     back quad k (the diagonal is the shared edge). This is the one to compare with qsp and with
//     `draco_encoder -preserve_polygons`.
//   triangles: the cache-optimized triangle order as is; quads can no longer be recovered.
// Positions: float32 x,y,z (12 bytes a vertex, lossless), and quantized to N bits (default 14, the
// grid of `qsp compress --quantize N` and `draco_encoder -qp N`: uniform over the bounding box's
// largest extent) stored as uint16 x,y,z plus a zero pad (meshopt's vertex codec wants a multiple of
// 4 bytes; the pad costs next to nothing after the codec). Every stream is decoded again and checked.
// Unreferenced vertices are dropped by optimizeVertexFetch (none in the benchmark's meshes).
#include <meshoptimizer.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "qsp/io.h"

namespace {

using Bytes = std::vector<unsigned char>;

std::size_t zstd_size(const Bytes& data, int level) {
  Bytes out(ZSTD_compressBound(data.size()));
  const std::size_t n = ZSTD_compress(out.data(), out.size(), data.data(), data.size(), level);
  if (ZSTD_isError(n)) {
    std::fprintf(stderr, "meshopt_codec: zstd: %s\n", ZSTD_getErrorName(n));
    std::exit(1);
  }
  return n;
}

void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "meshopt_codec: round trip failed: %s\n", what);
    std::exit(1);
  }
}

Bytes encode_indices(const std::vector<unsigned>& tris, std::size_t vertex_count) {
  Bytes out(meshopt_encodeIndexBufferBound(tris.size(), vertex_count));
  out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), tris.data(), tris.size()));
  std::vector<unsigned> back(tris.size());
  check(meshopt_decodeIndexBuffer(back.data(), back.size(), sizeof(unsigned), out.data(), out.size()) == 0,
        "index decode");
  // The encoder may rotate each triangle's corners; compare triangles up to rotation.
  for (std::size_t t = 0; t < tris.size(); t += 3) {
    bool same = false;
    for (int r = 0; r < 3 && !same; ++r)
      same = back[t] == tris[t + r] && back[t + 1] == tris[t + (r + 1) % 3] && back[t + 2] == tris[t + (r + 2) % 3];
    check(same, "index buffer");
  }
  return out;
}

Bytes encode_vertices(const void* data, std::size_t count, std::size_t stride) {
  Bytes out(meshopt_encodeVertexBufferBound(count, stride));
  out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data, count, stride));
  Bytes back(count * stride);
  check(meshopt_decodeVertexBuffer(back.data(), count, stride, out.data(), out.size()) == 0, "vertex decode");
  check(std::memcmp(back.data(), data, back.size()) == 0, "vertex buffer");
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int bits = 14;
  bool tsv = false;
  std::string path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--bits" && i + 1 < argc) {
      bits = std::atoi(argv[++i]);
    } else if (a == "--tsv") {
      tsv = true;
    } else if (!a.empty() && a[0] != '-' && path.empty()) {
      path = a;
    } else {
      std::fprintf(stderr, "usage: meshopt_codec [--bits N] [--tsv] MESH\n");
      return 2;
    }
  }
  if (path.empty() || bits < 1 || bits > 16) {
    std::fprintf(stderr, "usage: meshopt_codec [--bits N (1-16)] [--tsv] MESH\n");
    return 2;
  }
  qsp::QuadMesh mesh;
  try {
    qsp::ReadReport report;  // extra attributes are ignored, as with --positions-only
    mesh = qsp::read_mesh_file(path, &report);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meshopt_codec: %s\n", e.what());
    return 1;
  }
  const std::size_t nv = mesh.vertex_count(), nq = mesh.face_count();
  meshopt_encodeIndexVersion(1);
  meshopt_encodeVertexVersion(0);

  // Quads -> triangles (a,b,c), (a,c,d); triangle 2q and 2q+1 belong to quad q.
  std::vector<unsigned> tris(nq * 6);
  for (std::size_t q = 0; q < nq; ++q) {
    const std::uint32_t* f = &mesh.quads[4 * q];
    const unsigned t[6] = {f[0], f[1], f[2], f[0], f[2], f[3]};
    std::copy(t, t + 6, &tris[6 * q]);
  }
  // Cache optimization reorders triangles; find where each triangle went by a lookup on its corners.
  std::vector<unsigned> opt(tris.size());
  meshopt_optimizeVertexCache(opt.data(), tris.data(), tris.size(), nv);

  // "quads kept": quads in order of their first triangle in the optimized list, triangles paired.
  std::vector<unsigned> quad_tris;
  {
    // Key a triangle by its corners rotated so the smallest comes first (orientation kept).
    auto key = [](const unsigned* t) {
      int m = 0;
      if (t[1] < t[m]) m = 1;
      if (t[2] < t[m]) m = 2;
      return std::array<unsigned, 3>{t[m], t[(m + 1) % 3], t[(m + 2) % 3]};
    };
    std::vector<std::pair<std::array<unsigned, 3>, std::size_t>> index;  // key -> quad
    index.reserve(2 * nq);
    for (std::size_t t = 0; t < 2 * nq; ++t) index.emplace_back(key(&tris[3 * t]), t / 2);
    std::sort(index.begin(), index.end());
    std::vector<char> placed(nq, 0);
    quad_tris.reserve(tris.size());
    for (std::size_t t = 0; t < 2 * nq; ++t) {
      const auto k = key(&opt[3 * t]);
      auto it = std::lower_bound(index.begin(), index.end(), std::make_pair(k, std::size_t{0}));
      check(it != index.end() && it->first == k, "triangle lookup");
      const std::size_t q = it->second;
      if (placed[q]) continue;
      placed[q] = 1;
      quad_tris.insert(quad_tris.end(), &tris[6 * q], &tris[6 * q + 6]);
    }
    check(quad_tris.size() == tris.size(), "every quad placed");
  }

  // Vertex fetch order is taken from the quad-kept list (it renumbers vertices in first-use order);
  // the triangle-only variant gets its own.
  auto fetch = [&](std::vector<unsigned>& list, std::vector<float>& pos) {
    pos.assign(mesh.positions.size(), 0.0f);
    const std::size_t used = meshopt_optimizeVertexFetch(pos.data(), list.data(), list.size(),
                                                         mesh.positions.data(), nv, 3 * sizeof(float));
    pos.resize(3 * used);
    return used;
  };
  std::vector<float> pos_q, pos_t;
  const std::size_t used = fetch(quad_tris, pos_q);
  fetch(opt, pos_t);

  const Bytes idx_quads = encode_indices(quad_tris, used);
  const Bytes idx_tris = encode_indices(opt, used);
  const Bytes vtx_f32 = encode_vertices(pos_q.data(), used, 3 * sizeof(float));

  // N-bit quantization over the bounding box's largest extent, stored as uint16 x,y,z,0.
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (std::size_t v = 0; v < used; ++v)
    for (int c = 0; c < 3; ++c) {
      const float x = pos_q[3 * v + c];
      if (v == 0 || x < lo[c]) lo[c] = x;
      if (v == 0 || x > hi[c]) hi[c] = x;
    }
  const double extent = std::max({double(hi[0]) - lo[0], double(hi[1]) - lo[1], double(hi[2]) - lo[2]});
  const double scale = extent > 0 ? ((1u << bits) - 1) / extent : 0.0;
  std::vector<std::uint16_t> qpos(4 * used, 0);
  for (std::size_t v = 0; v < used; ++v)
    for (int c = 0; c < 3; ++c)
      qpos[4 * v + c] = static_cast<std::uint16_t>(std::lround((double(pos_q[3 * v + c]) - lo[c]) * scale));
  const Bytes vtx_q = encode_vertices(qpos.data(), used, 4 * sizeof(std::uint16_t));

  const int level = 19;
  const std::size_t zi_q = zstd_size(idx_quads, level), zi_t = zstd_size(idx_tris, level);
  const std::size_t zv_f = zstd_size(vtx_f32, level), zv_q = zstd_size(vtx_q, level);
  if (tsv) {
    // vertices quads idx_quads_zstd idx_tris_zstd vtx_f32_zstd vtx_quant_zstd
    std::printf("%zu\t%zu\t%zu\t%zu\t%zu\t%zu\n", used, nq, zi_q, zi_t, zv_f, zv_q);
    return 0;
  }
  const double bpv = 8.0 / double(used ? used : 1);
  std::printf("%s: %zu vertices, %zu quads encoded as %zu triangles (a,b,c)+(a,c,d)\n", path.c_str(), used, nq,
              2 * nq);
  std::printf("meshoptimizer %d.%d, index codec v1, vertex codec v0, then zstd -%d per stream\n",
              MESHOPTIMIZER_VERSION / 1000, MESHOPTIMIZER_VERSION / 10 % 100,
              level);
  std::printf("%-44s %10s %10s %8s\n", "stream", "encoded", "+zstd", "bits/v");
  auto row = [&](const char* name, const Bytes& b, std::size_t z) {
    std::printf("%-44s %10zu %10zu %8.2f\n", name, b.size(), z, double(z) * bpv);
  };
  row("index, quads kept (triangles paired)", idx_quads, zi_q);
  row("index, triangles (quads not recoverable)", idx_tris, zi_t);
  row("vertex, float32 xyz (lossless)", vtx_f32, zv_f);
  char name[64];
  std::snprintf(name, sizeof name, "vertex, %d-bit quantized (uint16 xyz+pad)", bits);
  row(name, vtx_q, zv_q);
  std::printf("total lossless %zu bytes, %d-bit %zu bytes (quads kept)\n", zi_q + zv_f, bits, zi_q + zv_q);
  return 0;
}
