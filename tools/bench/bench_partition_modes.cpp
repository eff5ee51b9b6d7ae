// Schematic size per partition mode (motorcycle, greedy, merge) on mesh files: the §7 comparison.
// Build and run with tools/bench/bench_partition_modes.sh (or, with QSP_BUILD_BENCH=ON, the
// bench_partition_modes target). Usage: bench_partition_modes FILE...
// Prints one row per file that partitions: per mode the schematic vertices V, edges E, patches P and
// T, the bytes of the entropy-coded topology section (encode_topology of the canonical codes: the
// connectivity part of a .qsp), then medians of the per-file ratios to motorcycle. Files that do not
// load are listed and skipped.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "codec_sections.h"
#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "qsp/smaller.h"

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string base(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace qsp;
  const PartitionMode modes[3] = {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge};
  std::printf("%-40s %7s %6s |", "model", "faces", "xord");
  for (PartitionMode m : modes)
    std::printf(" %-10s %5s %5s %5s %6s |", partition_mode_name(m), "V", "E", "P", "T");
  std::printf(" %7s %7s\n", "E g/m", "E mg/m");
  std::vector<double> tratio_greedy, tratio_merge;
  std::vector<double> ratio_greedy, ratio_merge, vratio_greedy, vratio_merge, pratio_greedy, pratio_merge;
  double time_ms[3] = {0, 0, 0};
  int invalid = 0;
  for (int i = 1; i < argc; ++i) {
    QuadMesh mesh;
    Adjacency adj;
    try {
      mesh = read_mesh_file(argv[i]);
      adj = build_adjacency(mesh);
    } catch (const Error& e) {
      std::printf("%-40s skipped: %s\n", base(argv[i]).c_str(), e.what());
      continue;
    }
    PartitionSize z[3];
    std::size_t topo[3];
    for (int k = 0; k < 3; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      const Partition p = partition(adj, modes[k]);
      time_ms[k] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      for (const auto& c : p.components)
        if (!validate(c, &adj).empty()) ++invalid;
      z[k] = partition_size(p);
      std::vector<TopologyCode> codes;
      for (const auto& c : canonicalize(mesh, adj, p).components) codes.push_back(c.code);
      topo[k] = encode_topology(codes).size();
    }
    std::printf("%-40s %7zu %6zu |", base(argv[i]).c_str(), mesh.face_count(),
                extraordinary_vertices(adj).size());
    for (int k = 0; k < 3; ++k)
      std::printf(" %-10s %5llu %5llu %5llu %6zu |", "", (unsigned long long)z[k].vertices,
                  (unsigned long long)z[k].edges, (unsigned long long)z[k].patches, topo[k]);
    const double e0 = std::max<double>(1, double(z[0].edges));
    std::printf(" %6.1f%% %6.1f%%\n", 100.0 * z[1].edges / e0, 100.0 * z[2].edges / e0);
    if (z[0].edges == 0) continue;  // structured meshes: nothing to compare
    ratio_greedy.push_back(double(z[1].edges) / z[0].edges);
    ratio_merge.push_back(double(z[2].edges) / z[0].edges);
    vratio_greedy.push_back(double(z[1].vertices) / z[0].vertices);
    vratio_merge.push_back(double(z[2].vertices) / z[0].vertices);
    pratio_greedy.push_back(double(z[1].patches) / z[0].patches);
    pratio_merge.push_back(double(z[2].patches) / z[0].patches);
    tratio_greedy.push_back(double(topo[1]) / topo[0]);
    tratio_merge.push_back(double(topo[2]) / topo[0]);
  }
  std::printf(
      "\nmedian over %zu meshes, relative to motorcycle:  greedy V %.1f%% E %.1f%% P %.1f%% T %.1f%%   "
      "merge V %.1f%% E %.1f%% P %.1f%% T %.1f%%\n",
      ratio_greedy.size(), 100 * median(vratio_greedy), 100 * median(ratio_greedy),
      100 * median(pratio_greedy), 100 * median(tratio_greedy), 100 * median(vratio_merge),
      100 * median(ratio_merge), 100 * median(pratio_merge), 100 * median(tratio_merge));
  std::printf("total time: motorcycle %.0f ms, greedy %.0f ms, merge %.0f ms; invalid components: %d\n",
              time_ms[0], time_ms[1], time_ms[2], invalid);
  return invalid ? 1 : 0;
}
