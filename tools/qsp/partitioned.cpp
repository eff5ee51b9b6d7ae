#include "partitioned.h"

#include <CLI/CLI.hpp>

#include "load.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/smaller.h"

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

PartitionedMesh load_partitioned(const std::string& path, const std::string& partition) {
  PartitionedMesh pm;
  Partition part;
  const bool qsp_file = format_from_path(path) == MeshFormat::kQsp;
  if (partition == "stored" && !qsp_file)
    throw CLI::ValidationError("--partition stored needs a .qsp input; " + path + " is a mesh");
  if (qsp_file) {
    const std::string bytes = read_file_bytes(path);
    try {
      pm.mesh = decode(bytes);
      pm.adjacency = build_adjacency(pm.mesh);
      if (partition.empty() || partition == "stored") {
        part =
            stored_partition(pm.adjacency, file_topology(bytes).codes, canonical_to_mesh(file_order(bytes)));
        pm.label = "stored";
      }
    } catch (const Error& e) {
      throw Error(e.code(), path + ": " + e.what());
    }
  } else {
    LoadedMesh loaded = load_mesh(path);
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
