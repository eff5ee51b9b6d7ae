// tools/qsp/partitioned.h: a mesh or .qsp read with the partition `show` and `layout` draw or export.
#pragma once

#include <string>

#include "qsp/canonical.h"
#include "qsp/io.h"
#include "qsp/layout_export.h"
#include "qsp/mesh.h"
#include "qsp/submesh.h"

namespace qsp::cli {

struct PartitionedMesh {
  QuadMesh mesh;  // the quads partitioned: the mesh, or a polygon mesh's quad submesh (qsp/submesh.h)
  Adjacency adjacency;
  CanonicalMesh canonical;
  PolygonMesh drawn;     // the mesh as read, faces of any degree: what show draws and --patches writes
  PatchView view;        // the partition on `drawn` (polygon_view for a polygon mesh)
  std::string label;     // which partition: a PartitionMode name, "auto (NAME)" or "stored"
  std::string rounding;  // a mesh input's ReadReport::describe_rounding: empty if nothing was rounded
};

// The --partition values show and layout accept, for CLI11's check and the help text.
inline constexpr const char* kPartitionHelp =
    "Partition: motorcycle (default for a mesh), greedy, merge, auto (the one compress would store), or "
    "stored (default for a .qsp: the partition the file holds)";

// Reads `path` (a mesh, or a .qsp decoded in full; read_polygon_input, shared.h, with `format`
// from --format) and partitions it (a polygon mesh: its quad submesh, where "auto" is the motorcycle
// graph compress's default level stores and "stored" is refused): `partition` is "" (a .qsp's stored
// partition, a mesh's motorcycle graph), "stored"
// (.qsp only), "auto" or a PartitionMode name. Throws qsp::Error located at the file (kUsage-like errors
// as CLI::ValidationError).
PartitionedMesh load_partitioned(const std::string& path, const std::string& partition, MeshFormat format);

// One comment line naming the input and partition, for exported files.
std::string describe(const std::string& path, const PartitionedMesh& pm);

}  // namespace qsp::cli
