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

PartitionMode mode_of(const std::string& partition) {
  PartitionMode mode = PartitionMode::kMotorcycle;
  if (!partition.empty() && !parse_partition_mode(partition, mode))
    throw CLI::ValidationError("--partition: unknown partition " + partition);
  return mode;
}

// A polygon mesh (faces of any degree, non-manifold or mis-oriented pieces): the partition of its quad
// submesh (qsp/submesh.h), drawn on the mesh itself. `from_qsp`: decoded from a 3.1 file.
PartitionedMesh polygon_partitioned(PolygonMesh mesh, const std::string& path, const std::string& partition,
                                    bool from_qsp) {
  if (partition == "stored")
    throw CLI::ValidationError("--partition stored: " + path +
                               " holds a polygon mesh, whose stored partition is not read yet; its quad "
                               "submesh's partitions are: motorcycle, greedy, merge, auto");
  PartitionedMesh pm;
  QuadSubmesh sub = quad_submesh(mesh.face_offsets, mesh.corners,
                                 static_cast<std::uint32_t>(mesh.vertex_count()), mesh.positions);
  PartitionMode mode = mode_of(partition == "auto" ? "" : partition);
  if (partition == "auto") {
    // What compress stores at its default level: the motorcycle graph unless the level searches.
    if (level_effort(kDefaultLevel, sub.mesh.vertex_count()).all_partitions)
      throw CLI::ValidationError("--partition auto on a polygon mesh: name the partition");
    pm.label = "auto (motorcycle)";
  } else {
    pm.label = partition_mode_name(mode);
  }
  if (from_qsp && partition.empty()) pm.label += " (of the decoded polygon mesh's quads)";
  const Partition part = qsp::partition(sub.adjacency, mode, sub.mesh.positions);
  pm.canonical = canonicalize(sub.mesh, sub.adjacency, part);
  pm.view = polygon_view(sub, view_partition(sub.adjacency, pm.canonical), mesh.face_count());
  pm.mesh = std::move(sub.mesh);
  pm.adjacency = std::move(sub.adjacency);
  pm.drawn = std::move(mesh);
  return pm;
}

}  // namespace

PartitionedMesh load_partitioned(const std::string& path, const std::string& partition, MeshFormat format) {
  PolygonInput in = read_polygon_input(path, format);
  if (!in.qsp && !in.quads) {  // a polygon mesh, from a mesh file or a .qsp
    PartitionedMesh pm = polygon_partitioned(std::move(in.polygons), path, partition, in.from_qsp);
    pm.rounding = in.report.describe_rounding(path);
    return pm;
  }
  if (partition == "stored" && !in.qsp)
    throw CLI::ValidationError("--partition stored needs a .qsp input; " + path + " is a mesh");
  PartitionedMesh pm;
  Partition part;
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
    try {
      pm.adjacency = build_adjacency(in.mesh);
    } catch (const Error& e) {
      // Quads only, but non-manifold or mis-oriented: cut apart as any polygon mesh is.
      if (!polygon_path_takes(e)) rethrow_located(e, path, in.report);
      std::string rounding = std::move(pm.rounding);
      pm = polygon_partitioned(polygon_mesh(std::move(in.mesh)), path, partition, false);
      pm.rounding = std::move(rounding);
      return pm;
    }
    pm.mesh = std::move(in.mesh);
  }
  if (pm.label.empty()) {
    if (partition == "auto") {
      // What compress stores: its file's partition, found on this mesh through the encoder's order map.
      OrderMap order;
      const std::string bytes = encode(pm.mesh, {}, &order);
      part = stored_partition(pm.adjacency, file_topology(bytes).codes, canonical_to_mesh(order));
      pm.label = "auto";
    } else {
      const PartitionMode mode = mode_of(partition);
      part = qsp::partition(pm.adjacency, mode, pm.mesh.positions);
      pm.label = partition_mode_name(mode);
    }
  }
  pm.canonical = canonicalize(pm.mesh, pm.adjacency, part);
  pm.view = view_partition(pm.adjacency, pm.canonical);
  pm.drawn = polygon_mesh(pm.mesh);
  return pm;
}

std::string describe(const std::string& path, const PartitionedMesh& pm) {
  std::string name = path;
  for (char& c : name)
    if (static_cast<unsigned char>(c) < 0x20) c = '?';  // one comment line, whatever the file name
  return "qsp: " + name + ", " + pm.label + " partition, " + std::to_string(pm.view.patch_count) + " patches";
}

}  // namespace qsp::cli
