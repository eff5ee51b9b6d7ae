// Adjacency + motorcycle graph + schematic on refined cubes, and the sublinear tracing path (§5).
// Run: cmake -B build-bench -DQSP_BUILD_BENCH=ON && cmake --build build-bench --target bench_partition
//      ./build-bench/bench_partition
#include <benchmark/benchmark.h>

#include <map>

#include "../../tests/support/mesh_gen.h"
#include "qsp/canonical.h"
#include "qsp/partition.h"

namespace {

// Cube refined `level` times: (2^level)^2 quads per side, 8 extraordinary vertices.
const qsp::QuadMesh& cube(int level) {
  static std::map<int, qsp::QuadMesh> cache;
  auto it = cache.find(level);
  if (it == cache.end()) it = cache.emplace(level, qsp::testing::cube(1 << level)).first;
  return it->second;
}

void BM_AdjacencyMotorcycleSchematic(benchmark::State& state) {
  const qsp::QuadMesh& m = cube(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const qsp::Adjacency adj = qsp::build_adjacency(m);
    qsp::Partition p = qsp::partition_motorcycle(adj);
    benchmark::DoNotOptimize(p);
  }
  state.counters["faces"] = static_cast<double>(m.face_count());
}
BENCHMARK(BM_AdjacencyMotorcycleSchematic)->Arg(7)->Arg(9)->Unit(benchmark::kMillisecond);

void BM_Adjacency(benchmark::State& state) {
  const qsp::QuadMesh& m = cube(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(qsp::build_adjacency(m));
}
BENCHMARK(BM_Adjacency)->Arg(9)->Unit(benchmark::kMillisecond);

void BM_CanonicalizeAfterPartition(benchmark::State& state) {
  const qsp::QuadMesh& m = cube(static_cast<int>(state.range(0)));
  const qsp::Adjacency adj = qsp::build_adjacency(m);
  const qsp::Partition p = qsp::partition_motorcycle(adj);
  for (auto _ : state) benchmark::DoNotOptimize(qsp::canonicalize(m, adj, p));
}
BENCHMARK(BM_CanonicalizeAfterPartition)->Arg(9)->Unit(benchmark::kMillisecond);

// Tracing alone, given the adjacency and the list of extraordinary vertices: time should follow the
// traced edges (x2 per level), not the faces (x4 per level).
void BM_TraceSublinear(benchmark::State& state) {
  const qsp::QuadMesh& m = cube(static_cast<int>(state.range(0)));
  const qsp::Adjacency adj = qsp::build_adjacency(m);
  const std::vector<std::uint32_t> xv = qsp::extraordinary_vertices(adj);
  std::size_t traced = 0;
  for (auto _ : state) {
    qsp::MotorcycleGraph g = qsp::trace_motorcycles(adj, xv);
    traced = g.traced.size();
    benchmark::DoNotOptimize(g);
  }
  state.counters["traced_edges"] = static_cast<double>(traced);
  state.counters["faces"] = static_cast<double>(m.face_count());
}
BENCHMARK(BM_TraceSublinear)->DenseRange(5, 9)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
