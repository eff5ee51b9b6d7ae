// Highway meshes (§8) against the known optimum: for each seed, a random arrangement of n segments,
// its highway mesh, k by brute force, the optimal schematic size (checked by cutting the mesh along the
// optimal casing), and each partition mode's size relative to it.
// Build and run with tools/bench/bench_partition_modes.sh, or by hand:
//   g++ -std=c++20 -O2 -Iinclude tools/highway/highway.cpp build/libqsp.a -lpthread -lz
// The generator itself is tests/support/highway.h, which the tests (test_smaller.cpp) use too.
// Usage: highway [--seeds N] [--first S] [--segments N] [--size S] [--obj DIR]
//   --obj DIR writes DIR/highway_<seed>.obj for every mesh.
#include "../../tests/support/highway.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "qsp/io.h"
#include "qsp/partition.h"
#include "qsp/smaller.h"

int main(int argc, char** argv) {
  using namespace qsp;
  int seeds = 20, segments = 10, size = 24;
  std::uint64_t first = 1;
  std::string obj_dir;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--seeds"))
      seeds = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--first"))
      first = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--segments"))
      segments = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--size"))
      size = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--obj"))
      obj_dir = argv[i + 1];
    else {
      std::fprintf(stderr, "unknown option %s\n", argv[i]);
      return 2;
    }
  }
  const PartitionMode modes[3] = {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge};
  std::printf("%6s %3s %3s %3s | %5s %5s %4s |", "seed", "n", "j", "k", "optV", "optE", "optP");
  for (PartitionMode m : modes)
    std::printf(" %-10s %5s %5s %4s %6s |", partition_mode_name(m), "V", "E", "P", "E/opt");
  std::printf("\n");
  double worst[3] = {0, 0, 0}, sum[3] = {0, 0, 0};
  int rows = 0, bad = 0;
  for (int r = 0; r < seeds; ++r) {
    const std::uint64_t seed = first + r;
    const highway::Arrangement arr = highway::random_arrangement(seed, segments, size);
    const highway::HighwayMesh h = highway::build(arr);
    const Adjacency adj = build_adjacency(h.mesh);
    const std::vector<int> visible = highway::max_noncrossing(arr);
    const int k = static_cast<int>(visible.size());
    const highway::Counts opt = highway::optimal_counts(h.n, h.j, k);
    // The formula is checked, not assumed: cut along the optimal casing and count.
    const PartitionSize cased =
        partition_size(partition_from_cuts(adj, highway::optimal_cuts(h, adj, visible)));
    if (std::int64_t(cased.vertices) != opt.vertices || std::int64_t(cased.edges) != opt.edges ||
        std::int64_t(cased.patches) != opt.patches) {
      std::printf("seed %llu: optimal casing gives %llu/%llu/%llu, formula %lld/%lld/%lld\n",
                  (unsigned long long)seed, (unsigned long long)cased.vertices,
                  (unsigned long long)cased.edges, (unsigned long long)cased.patches, (long long)opt.vertices,
                  (long long)opt.edges, (long long)opt.patches);
      ++bad;
    }
    if (!obj_dir.empty())
      write_file_atomic(obj_dir + "/highway_" + std::to_string(seed) + ".obj", write_obj(h.mesh), true);
    std::printf("%6llu %3d %3d %3d | %5lld %5lld %4lld |", (unsigned long long)seed, h.n, h.j, k,
                (long long)opt.vertices, (long long)opt.edges, (long long)opt.patches);
    for (int m = 0; m < 3; ++m) {
      const PartitionSize z = partition_size(partition(adj, modes[m]));
      const double ratio = double(z.edges) / double(opt.edges);
      worst[m] = std::max(worst[m], ratio);
      sum[m] += ratio;
      std::printf(" %-10s %5llu %5llu %4llu %6.3f |", "", (unsigned long long)z.vertices,
                  (unsigned long long)z.edges, (unsigned long long)z.patches, ratio);
    }
    std::printf("\n");
    ++rows;
  }
  std::printf("\nschematic edges / optimum over %d meshes:", rows);
  for (int m = 0; m < 3; ++m)
    std::printf("  %s mean %.3f worst %.3f", partition_mode_name(modes[m]), sum[m] / std::max(rows, 1),
                worst[m]);
  std::printf("\n%s\n", bad ? "FORMULA MISMATCH"
                            : "optimal casing matches 4j+10n-2k / 6j+12n-3k / j+3n-k on every mesh");
  return bad ? 1 : 0;
}
