// Writing a .qsp: one partition's file (codec_encode.cpp), and the choice among partitions and the
// threads that run them (encode_choice.cpp). Internal; tests reach encode_tuned through the private
// include path.
#pragma once

#include <cstdint>
#include <functional>
#include <future>
#include <optional>
#include <string>
#include <string_view>

#include "geometry_coder.h"
#include "qsp/codec.h"
#include "qsp/regions.h"

namespace qsp {

// What tests and goldens may fix beyond EncodeOptions: the geometry tools (geometry_tool bits, the
// layout-order bit aside), so that a golden pins each combination whatever the level would choose.
struct EncodeTuning {
  std::optional<std::uint8_t> geometry_tools;
  // Called with the order the encode hands back (OrderMap) once it is known, before the geometry is
  // coded, by an encode of one partition: the polygon codec codes the per-corner sections beside the
  // geometry from there.
  std::function<void(const OrderMap&)> order_known = nullptr;
};

// encode() with `tuning`. Same contract.
std::string encode_tuned(const QuadMesh& mesh, const EncodeOptions& options, const EncodeTuning& tuning,
                         OrderMap* order = nullptr);

// The geometry header choice (value repeats, decimal grid or float bits) that the encodes of one mesh
// share. Which header is smallest depends on the coordinates, hardly on the partition or the coding
// order, so only the first encode tries them all; on the 23 shared meshes, lossless and at 14 bits,
// the files are byte-identical to trying every header everywhere. Small meshes then run 7 geometry
// encodes at 14 bits and 9 lossless, not 12 and 24 (plus the normal-chaining trials).
struct SharedChoice {
  std::promise<GeometryChoice> chosen;  // set once, by the encode that chooses (or its failure)
  std::shared_future<GeometryChoice> future = chosen.get_future().share();
  bool set = false;
};

// How one encode_partition takes part: the one that chooses publishes its choice, the others wait for
// it (each with its own copy of the future, as threads must); without one, the encode chooses alone
// and reuses its choice for its second coding order.
struct ChoiceRole {
  SharedChoice* publish = nullptr;
  std::optional<std::shared_future<GeometryChoice>> wait;
};

// The file for `mesh` stored with `partition` (of `adj`, its adjacency), searched as `effort` says.
// If `order_out` is given it gets the original -> canonical map. Throws as encode() does.
std::string encode_partition(const QuadMesh& mesh, const Adjacency& adj, const Partition& partition,
                             const EncodeOptions& options, const Effort& effort, const EncodeTuning& tuning,
                             OrderMap* order_out, ChoiceRole role = {});

// A polygon mesh's interior vertices, which the geometry section codes after the layout's (format 3.12,
// the interior positions section): the faces the decoder rebuilds, whose fans give their stencils, and
// the positions of the owned interior refs in ref order (3 floats each).
struct InteriorGeometry {
  const PolygonFaces* faces = nullptr;
  std::vector<float> positions;
};

// encode_partition's file from `cm`, a canonical form of `mesh` (canonicalize's, or canonical_regions'
// re-rooted one). A non-empty `polygons` is stored as the polygons section (a 3.1 file), with
// `polygon_order` as its order section when that is not empty, and `interior` (when it has positions)
// coded by the geometry section, with an interior positions section; without a polygons section the file
// is 3.0. Throws as encode() does.
// `adjacency`: `mesh`'s, where the caller has it (the mirror search then renumbers it, not builds the
// layout's again).
std::string encode_canonical(const QuadMesh& mesh, const CanonicalMesh& cm, const EncodeOptions& options,
                             const Effort& effort, const EncodeTuning& tuning, OrderMap* order_out,
                             ChoiceRole role = {}, std::string_view polygons = {},
                             std::string_view polygon_order = {}, const InteriorGeometry* interior = nullptr,
                             const Adjacency* adjacency = nullptr);

// `adj` renumbered as `order` numbers the canonical layout (layout corner c of face order.face[f] is
// input corner (c + order.rotation[f]) mod 4; components by their first layout face): build_adjacency
// of the layout's quads but for which outgoing half-edge each vertex names and how the exterior
// half-edges are numbered, in O(half-edges) where building it again was a tenth of compressing mh_base.
Adjacency layout_adjacency(const Adjacency& adj, const OrderMap& order);

}  // namespace qsp
