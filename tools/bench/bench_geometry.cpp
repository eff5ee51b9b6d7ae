// Geometry coder on real meshes: bits per vertex (lossless and quantized) along the partition's grid
// stencils, against file order and a zstd baseline; then encode/decode speed (Google Benchmark).
//
//   cmake -S . -B build-bench -DQSP_BUILD_BENCH=ON && cmake --build build-bench --target bench_geometry
//   build-bench/bench_geometry [mesh files...] [--benchmark_filter=...]
// With no files it uses keenan_spot_quadrangulated.obj and mh_female_generic_cc2.obj from shared/meshes.
#include <benchmark/benchmark.h>
#include <zstd.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bytes.h"
#include "geometry_coder.h"
#include "layout_grid.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "stencil.h"

namespace {

using qsp::GridLayout;
using qsp::kInvalid;
using qsp::Stencil;

// Positions in coding order with their stencils, as the codec builds them: every component's layout in
// `order`, one after the other, then the unreferenced vertices (no neighbours).
struct Coded {
  std::vector<float> positions;
  std::vector<Stencil> stencil;
  qsp::CodingOrder order = qsp::CodingOrder::kLayout;
};

Coded coding_order(const qsp::QuadMesh& mesh, qsp::CodingOrder order) {
  const qsp::Adjacency adj = qsp::build_adjacency(mesh);
  const qsp::Partition part = qsp::partition_motorcycle(adj);
  Coded c;
  c.order = order;
  for (const auto& comp : part.components) {
    qsp::Numbering n;
    const GridLayout g = qsp::grid_layout(comp, n);
    const qsp::ComponentStencils layout = qsp::component_stencils(comp, g, n, order);
    const qsp::LayoutMap map = qsp::layout_to_mesh(comp, adj);
    const auto base = static_cast<std::uint32_t>(c.stencil.size());
    for (std::uint32_t k = 0; k < g.vertex_count; ++k) {
      Stencil s = layout.stencil[k];
      for (std::uint32_t* j : s.vertex_fields())
        if (*j != kInvalid) *j += base;
      c.stencil.push_back(s);
      const std::uint32_t v = layout.coding.empty() ? k : layout.coding[k];
      for (int a = 0; a < 3; ++a) c.positions.push_back(mesh.positions[3 * map.vertex[v] + a]);
    }
  }
  for (std::uint32_t v : part.unreferenced) {
    c.stencil.push_back({});
    for (int a = 0; a < 3; ++a) c.positions.push_back(mesh.positions[3 * v + a]);
  }
  return c;
}

// Lower bound without a partition: each vertex predicted from the previous one in file order.
Coded file_order(const qsp::QuadMesh& mesh) {
  Coded c{mesh.positions, std::vector<Stencil>(mesh.vertex_count())};
  for (std::uint32_t i = 1; i < c.stencil.size(); ++i) c.stencil[i].w = i - 1;
  return c;
}

double bits_per_vertex(const Coded& c, std::uint32_t bits, double* max_error = nullptr) {
  const std::string bytes = qsp::encode_geometry(c.positions, c.stencil, {bits, c.order});
  const std::vector<float> back =
      qsp::decode_geometry(bytes, 0, c.stencil, static_cast<std::uint32_t>(c.stencil.size()));
  const double err = qsp::max_geometry_error(c.positions, back);
  if (bits == 0 && err != 0) std::fprintf(stderr, "LOSSLESS ROUND TRIP FAILED\n");
  if (max_error) *max_error = err;
  return bytes.size() * 8.0 / static_cast<double>(c.stencil.size());
}

// Baseline: the same grid quantization and predictors (parallelogram, 2w-ww, w), residuals zigzagged
// into LEB128 varints, one stream per axis and predictor kind, each through zstd -19.
double zstd_baseline_bits(const Coded& c, std::uint32_t bits) {
  const std::size_t n = c.stencil.size();
  std::vector<std::int64_t> q(c.positions.size());
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = hi[a] = c.positions.empty() ? 0 : c.positions[a];
    for (std::size_t i = a; i < c.positions.size(); i += 3) {
      lo[a] = std::min(lo[a], c.positions[i]);
      hi[a] = std::max(hi[a], c.positions[i]);
    }
  }
  double extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, double{hi[a]} - lo[a]);
  const double step = extent / ((1u << bits) - 1);
  for (std::size_t i = 0; i < c.positions.size(); ++i)
    q[i] = std::llround((c.positions[i] - lo[i % 3]) / step);
  std::vector<std::string> streams(3 * 4);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& s = c.stencil[i];
    for (int a = 0; a < 3; ++a) {
      auto at = [&](std::uint32_t j) { return q[3 * j + a]; };
      std::int64_t pred = 0;
      int kind = 0;
      if (s.w != kInvalid && s.s != kInvalid && s.sw != kInvalid) {
        pred = at(s.w) + at(s.s) - at(s.sw), kind = 3;
      } else if (s.w != kInvalid && s.ww != kInvalid) {
        pred = 2 * at(s.w) - at(s.ww), kind = 2;
      } else if (s.w != kInvalid) {
        pred = at(s.w), kind = 1;
      } else if (s.s != kInvalid) {
        pred = at(s.s), kind = 1;
      } else if (i > 0) {
        pred = at(static_cast<std::uint32_t>(i - 1));
      }
      const std::int64_t r = q[3 * i + a] - pred;
      std::uint64_t u = (static_cast<std::uint64_t>(r) << 1) ^ static_cast<std::uint64_t>(r >> 63);
      qsp::put_varint(streams[a * 4 + kind], u);
    }
  }
  std::size_t total = 0;
  for (const std::string& s : streams) {
    if (s.empty()) continue;
    std::string out(ZSTD_compressBound(s.size()), '\0');
    total += ZSTD_compress(out.data(), out.size(), s.data(), s.size(), 19) + 4;  // + a length field
  }
  return total * 8.0 / static_cast<double>(n);
}

std::vector<Coded> g_coded;
std::vector<std::string> g_names;  // per entry of g_coded

// Args: mesh, bits, coder thread (0 off, 1 on: GeometryOptions::coder_thread).
void BM_Encode(benchmark::State& state) {
  const Coded& c = g_coded[state.range(0)];
  const auto bits = static_cast<std::uint32_t>(state.range(1));
  qsp::GeometryOptions options{bits, c.order};
  options.coder_thread = state.range(2) != 0;
  for (auto _ : state) benchmark::DoNotOptimize(qsp::encode_geometry(c.positions, c.stencil, options));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(c.stencil.size()));
  state.SetLabel(g_names[state.range(0)]);
}

void BM_Decode(benchmark::State& state) {
  const Coded& c = g_coded[state.range(0)];
  const auto bits = static_cast<std::uint32_t>(state.range(1));
  const std::string bytes = qsp::encode_geometry(c.positions, c.stencil, {bits, c.order});
  const auto n = static_cast<std::uint32_t>(c.stencil.size());
  for (auto _ : state) benchmark::DoNotOptimize(qsp::decode_geometry(bytes, 0, c.stencil, n));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
  state.SetLabel(g_names[state.range(0)]);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  std::vector<std::string> files(argv + 1, argv + argc);
  if (files.empty()) {
    const std::string dir = std::string(QSP_SHARED_DIR) + "/meshes/";
    files = {dir + "keenan_spot_quadrangulated.obj", dir + "mh_female_generic_cc2.obj"};
  }
  std::printf("%-36s %8s | %9s %9s %9s | %9s %9s %11s | %9s %9s\n", "mesh", "V", "lossless", "14-bit",
              "layout:14", "file:loss", "file:14", "zstd:14", "err14", "enc ms");
  for (const std::string& file : files) {
    try {
      const qsp::QuadMesh mesh = qsp::read_mesh_file(file);
      Coded c = coding_order(mesh, qsp::CodingOrder::kPatch);
      const Coded f = file_order(mesh);
      double err14 = 0;
      const auto t0 = std::chrono::steady_clock::now();
      const double lossless = bits_per_vertex(c, 0);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const double q14 = bits_per_vertex(c, 14, &err14);
      std::printf("%-36s %8zu | %9.2f %9.2f %9.2f | %9.2f %9.2f %11.2f | %9.2e %9.1f\n",
                  std::filesystem::path(file).filename().string().c_str(), c.stencil.size(), lossless, q14,
                  bits_per_vertex(coding_order(mesh, qsp::CodingOrder::kLayout), 14), bits_per_vertex(f, 0),
                  bits_per_vertex(f, 14), zstd_baseline_bits(c, 14), err14, ms);
      g_coded.push_back(std::move(c));
    } catch (const qsp::Error& e) {
      std::printf("%-36s skipped: %s\n", file.c_str(), e.what());
      continue;
    }
    g_names.push_back(std::filesystem::path(file).filename().string());
  }
  for (std::size_t m = 0; m < g_coded.size(); ++m) {
    for (int bits : {0, 14}) {
      for (int thread : {0, 1}) {
        benchmark::RegisterBenchmark("encode", BM_Encode)
            ->Args({static_cast<long>(m), bits, thread})
            ->Unit(benchmark::kMillisecond);
      }
      benchmark::RegisterBenchmark("decode", BM_Decode)
          ->Args({static_cast<long>(m), bits})
          ->Unit(benchmark::kMillisecond);
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
