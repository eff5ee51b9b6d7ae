// src/polygon_fans.h (internal): a polygon mesh's glued edges and vertex fans (rules 1-4 of
// qsp/submesh.h), the one walk that cut_manifold and quad_submesh share.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace qsp::detail {

struct PolygonFans {
  std::vector<std::uint32_t> face_of;  // per corner: its face
  std::vector<std::uint32_t> twin;     // per corner (as half-edge): the glued half-edge, or kInvalid
  std::uint32_t cut_edges = 0;         // edges with 2+ faces left unglued (rule 1)
  // Fans of all faces (rule 2), numbered as first met scanning corners in increasing order.
  std::vector<std::uint32_t> corner_fan;  // per corner: its fan
  std::vector<std::uint32_t> fan_vertex;  // per fan: its original vertex
  std::vector<std::uint8_t> fan_quad;     // per fan: 1 if a quad has a corner in it
  // Quad fans (rule 3), numbered in the order the fan walk creates them.
  std::vector<std::uint32_t> qfan_vertex;  // per quad fan: its original vertex
  // Per corner: for a quad corner its quad fan; for a non-quad corner the quad fan it is attached to
  // (rule 4), kInvalid if its fan has no quad.
  std::vector<std::uint32_t> corner_qfan;
  // Per non-quad corner: the quad fan on the other side of its run of non-quad corners around the
  // vertex (the first clockwise), kInvalid if none; kInvalid at quad corners.
  std::vector<std::uint32_t> corner_qfan_other;
};

// Validates the arrays (see cut_manifold in qsp/submesh.h for the errors) and computes the above in
// O(corners + vertices).
PolygonFans polygon_fans(std::span<const std::uint32_t> face_offsets, std::span<const std::uint32_t> corners,
                         std::uint32_t vertex_count);

}  // namespace qsp::detail
