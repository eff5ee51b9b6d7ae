// Reading speed: qsp's OBJ parser (from memory and from a file) against OpenMesh::IO::read_mesh on
// the same file. Bytes/second counts the OBJ text size for every variant so the rates compare.
//   cmake -S . -B build-bench -DQSP_BUILD_BENCH=ON && cmake --build build-bench --target bench_read
//   build-bench/bench_read [--benchmark_filter=...] [mesh.obj]
#include <benchmark/benchmark.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <cstdio>
#include <string>

#include "qsp/error.h"
#include "qsp/io.h"

namespace {

std::string g_path = QSP_SHARED_DIR "/meshes/mh_female_generic_cc2.obj";

const std::string& file_bytes() {
  static const std::string bytes = qsp::read_file_bytes(g_path);
  return bytes;
}

void BM_QspReadObjMemory(benchmark::State& state) {
  const std::string& bytes = file_bytes();
  for (auto _ : state) {
    qsp::ReadReport report;
    qsp::QuadMesh mesh = qsp::read_obj(bytes, g_path, &report);
    benchmark::DoNotOptimize(mesh.quads.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(bytes.size()));
}

void BM_QspReadObjFile(benchmark::State& state) {
  const std::size_t size = file_bytes().size();  // warm the page cache like the other variants
  for (auto _ : state) {
    qsp::QuadMesh mesh = qsp::read_mesh_file(g_path);
    benchmark::DoNotOptimize(mesh.quads.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(size));
}

void BM_OpenMeshReadObjFile(benchmark::State& state) {
  const std::size_t size = file_bytes().size();
  for (auto _ : state) {
    OpenMesh::PolyMesh_ArrayKernelT<> mesh;
    OpenMesh::IO::Options options;
    if (!OpenMesh::IO::read_mesh(mesh, g_path, options))
      state.SkipWithError("OpenMesh could not read the file");
    benchmark::DoNotOptimize(mesh.n_faces());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(size));
}

BENCHMARK(BM_QspReadObjMemory)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_QspReadObjFile)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_OpenMeshReadObjFile)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (argc > 1) g_path = argv[1];  // optional mesh path after the benchmark flags
  try {
    benchmark::AddCustomContext("mesh", g_path);
    benchmark::AddCustomContext("mesh_bytes", std::to_string(file_bytes().size()));
  } catch (const qsp::Error& e) {
    std::fprintf(stderr, "bench_read: %s\n", e.what());
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
