#include "partitioned.h"

#include <CLI/CLI.hpp>

#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/smaller.h"
#include "shared.h"

namespace qsp::cli {
namespace {

// Canonical (decoder) vertex -> vertex of the mesh it was read or encoded from, from the order map
// (original vertex -> canonical); empty: the identity.
std::vector<std::uint32_t> canonical_to_mesh(const OrderMap& order) {
  std::vector<std::uint32_t> out(order.vertex.size());
  for (std::uint32_t v = 0; v < order.vertex.size(); ++v) out[order.vertex[v]] = v;
  return out;
}

}  // namespace

PartitionedMesh load_partitioned(const std::string& path, const std::string& partition, MeshFormat format) {
  PartitionedMesh pm;
  Partition part;
  Input in = read_input(path, format);
  if (partition == "stored" && !in.qsp)
    throw CLI::ValidationError("--partition stored needs a .qsp input; " + path + " is a mesh");
  if (in.qsp) {
    try {
      pm.mesh = decode(in.bytes);
      pm.adjacency = build_adjacency(pm.mesh);
      if (partition.empty() || partition == "stored") {
        part = stored_partition(pm.adjacency, file_topology(in.bytes).codes,
                                canonical_to_mesh(file_order(in.bytes)));
        pm.label = "stored";
      }
    } catch (const Error& e) {
      throw Error(e.code(), path + ": " + e.what());
    }
  } else {
    pm.rounding = in.report.describe_rounding(path);
    LoadedMesh loaded = with_adjacency(std::move(in.mesh), std::move(in.report), path);
    pm.mesh = std::move(loaded.mesh);
    pm.adjacency = std::move(loaded.adjacency);
  }
  if (pm.label.empty()) {
    if (partition == "auto") {
      // What compress stores: its file's partition, found on this mesh through the encoder's order map.
      OrderMap order;
      const std::string bytes = encode(pm.mesh, {}, &order);
      part = stored_partition(pm.adjacency, file_topology(bytes).codes, canonical_to_mesh(order));
      pm.label = "auto";
    } else {
      PartitionMode mode = PartitionMode::kMotorcycle;
      if (!partition.empty() && !parse_partition_mode(partition, mode))
        throw CLI::ValidationError("--partition: unknown partition " + partition);
      part = qsp::partition(pm.adjacency, mode, pm.mesh.positions);
      pm.label = partition_mode_name(mode);
    }
  }
  pm.canonical = canonicalize(pm.mesh, pm.adjacency, part);
  pm.view = view_partition(pm.adjacency, pm.canonical);
  return pm;
}

std::string describe(const std::string& path, const PartitionedMesh& pm) {
  std::string name = path;
  for (char& c : name)
    if (static_cast<unsigned char>(c) < 0x20) c = '?';  // one comment line, whatever the file name
  return "qsp: " + name + ", " + pm.label + " partition, " + std::to_string(pm.view.patch_count) + " patches";
}

}  // namespace qsp::cli
